#include "auth.h"

#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace partita::server {

bool constantTimeEquals(std::string_view given, std::string_view expected) {
    // Every byte of `expected` is looked at whatever `given` holds, so the time reveals neither
    // where the first difference is nor (beyond the loop count) anything about `given`.
    unsigned diff = given.size() == expected.size() ? 0u : 1u;
    for (size_t i = 0; i < expected.size(); ++i) {
        unsigned char g = i < given.size() ? static_cast<unsigned char>(given[i]) : 0u;
        diff |= unsigned(g ^ static_cast<unsigned char>(expected[i]));
    }
    return diff == 0;
}

TokenAuth TokenAuth::fromFile(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read token file '" + file.string() + "'");
    std::ostringstream s;
    s << in.rdbuf();
    std::string token = s.str();
    auto notSpace = [](unsigned char c) { return !std::isspace(c); };
    size_t b = 0, e = token.size();
    while (b < e && !notSpace(static_cast<unsigned char>(token[b]))) ++b;
    while (e > b && !notSpace(static_cast<unsigned char>(token[e - 1]))) --e;
    token = token.substr(b, e - b);
    if (token.empty()) throw std::runtime_error("token file '" + file.string() + "' is empty");
    for (unsigned char c : token)
        if (c < 0x21 || c > 0x7e)
            throw std::runtime_error("token file '" + file.string() +
                                     "' must hold one token of printable ASCII without spaces");
    return TokenAuth(std::move(token));
}

grpc::Status TokenAuth::check(const grpc::ServerContextBase& context) const {
    if (!enabled()) return grpc::Status::OK;
    const auto& md = context.client_metadata();
    auto it = md.find("authorization");
    if (it == md.end())
        return {grpc::StatusCode::UNAUTHENTICATED,
                "this server needs a token: send metadata 'authorization: Bearer <token>'"};
    return checkAuthorization(std::string_view(it->second.data(), it->second.size()));
}

grpc::Status TokenAuth::checkAuthorization(std::string_view value) const {
    if (!enabled()) return grpc::Status::OK;
    constexpr std::string_view kScheme = "bearer ";
    bool bearer = value.size() > kScheme.size();
    for (size_t i = 0; bearer && i < kScheme.size(); ++i)
        bearer = std::tolower(static_cast<unsigned char>(value[i])) == kScheme[i];
    if (!bearer)
        return {grpc::StatusCode::UNAUTHENTICATED, "the authorization must be 'Bearer <token>'"};
    if (!constantTimeEquals(value.substr(kScheme.size()), token_))
        return {grpc::StatusCode::UNAUTHENTICATED, "invalid token"};
    return grpc::Status::OK;
}

}  // namespace partita::server
