#include "http_access.h"

#include "server_options.h"

namespace partita::server::dashboard {

std::string cookieValue(const std::string& header, const std::string& name) {
    size_t pos = 0;
    while (pos < header.size()) {
        size_t end = header.find(';', pos);
        if (end == std::string::npos) end = header.size();
        std::string pair = header.substr(pos, end - pos);
        size_t start = pair.find_first_not_of(' ');
        if (start != std::string::npos) pair = pair.substr(start);
        if (pair.size() > name.size() && pair.compare(0, name.size(), name) == 0 &&
            pair[name.size()] == '=')
            return pair.substr(name.size() + 1);
        pos = end + 1;
    }
    return {};
}

bool isLoopbackHost(const std::string& hostHeader) {
    if (hostHeader.empty()) return false;
    // "[::1]:8080", "127.0.0.1:8080", "localhost": isLoopbackAddress wants host:port.
    std::string address = hostHeader;
    bool hasPort = address.front() == '[' ? address.find("]:") != std::string::npos
                                          : address.find(':') != std::string::npos;
    if (!hasPort) address += ":0";
    return isLoopbackAddress(address);
}

bool HttpAccess::tokenAccepted(const httplib::Request& request) const {
    if (request.has_header("Authorization"))
        return auth_.checkAuthorization(request.get_header_value("Authorization")).ok();
    if (request.has_param("token") && auth_.matches(request.get_param_value("token"))) return true;
    return auth_.matches(cookieValue(request.get_header_value("Cookie"), kTokenCookie));
}

grpc::Status HttpAccess::check(const httplib::Request& request) const {
    if (loopback_ && !isLoopbackHost(request.get_header_value("Host")))
        return {grpc::StatusCode::PERMISSION_DENIED,
                "this dashboard listens on loopback: address it as localhost or 127.0.0.1"};
    if (auth_.enabled() && !tokenAccepted(request))
        return {grpc::StatusCode::UNAUTHENTICATED,
                "this server needs a token: open the dashboard with ?token=<token> once, or send "
                "'Authorization: Bearer <token>'"};
    bool changes = request.method != "GET" && request.method != "HEAD";
    if (changes && request.get_header_value("X-Partita") != "1")
        return {grpc::StatusCode::PERMISSION_DENIED,
                "requests that change jobs must carry the header 'X-Partita: 1'"};
    return grpc::Status::OK;
}

std::string HttpAccess::loginCookie(const httplib::Request& request) const {
    if (!request.has_param("token") || !auth_.matches(request.get_param_value("token"))) return {};
    return std::string(kTokenCookie) + "=" + request.get_param_value("token") +
           "; Path=/; HttpOnly; SameSite=Strict" + (tls_ ? "; Secure" : "");
}

}  // namespace partita::server::dashboard
