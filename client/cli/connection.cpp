#include "cli/connection.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cli/file_util.h"

namespace partita::cli {

std::string readTokenFile(const std::string& path) {
    std::string text;
    try {
        text = readFile(path);
    } catch (const std::exception&) {
        throw CliError("cannot read token file '" + path + "'");
    }
    size_t end = text.find_first_of("\r\n");
    if (end != std::string::npos) text.resize(end);
    const char* ws = " \t";
    size_t b = text.find_first_not_of(ws);
    if (b == std::string::npos) throw CliError("token file '" + path + "' is empty");
    return text.substr(b, text.find_last_not_of(ws) - b + 1);
}

std::string withDefaultPort(const std::string& address) {
    if (address.empty() || address.find("://") != std::string::npos ||
        address.rfind("unix:", 0) == 0 || address.rfind("unix-abstract:", 0) == 0 ||
        address.rfind("dns:", 0) == 0 || address.rfind("ipv4:", 0) == 0 ||
        address.rfind("ipv6:", 0) == 0)
        return address;
    std::string out;
    const size_t colons = size_t(std::count(address.begin(), address.end(), ':'));
    if (address.front() == '[') {
        if (address.back() != ']') return address;  // "[v6]:port" already
        out = address;
    } else if (colons == 0) {
        out = address;
    } else if (colons > 1) {  // a bare IPv6 address
        out.append("[").append(address).append("]");
    } else {
        return address;
    }
    out.append(":").append(std::to_string(kDefaultPort));
    return out;
}

std::string loopbackForLocalhost(const std::string& address) {
    const std::string host = "localhost:";
    if (address.rfind(host, 0) != 0) return address;
    return "127.0.0.1:" + address.substr(host.size());
}

std::shared_ptr<grpc::Channel> makeChannel(const std::string& address, const ServerOptions& opts) {
    grpc::ChannelArguments args;
    // Retry a refused connection quickly while waiting for a daemon that is starting.
    args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 100);
    args.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 100);
    args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 500);
    // Results and raw preview frames can be large; the server limits what it sends.
    args.SetMaxReceiveMessageSize(-1);
    args.SetMaxSendMessageSize(-1);
    std::shared_ptr<grpc::ChannelCredentials> creds;
    if (!opts.tlsCa.empty()) {
        grpc::SslCredentialsOptions ssl;
        try {
            ssl.pem_root_certs = readFile(opts.tlsCa);
        } catch (const std::exception&) {
            throw CliError("cannot read TLS CA file '" + opts.tlsCa + "'");
        }
        if (!opts.tlsServerName.empty()) {
            args.SetSslTargetNameOverride(opts.tlsServerName);
        } else if (loopbackForLocalhost(address) != address) {
            args.SetSslTargetNameOverride("localhost");  // the name the user dialled
        }
        creds = grpc::SslCredentials(ssl);
    } else {
        creds = grpc::InsecureChannelCredentials();
    }
    return grpc::CreateCustomChannel(loopbackForLocalhost(address), creds, args);
}

Connection::Connection(const std::string& address, const ServerOptions& opts)
    : address_(withDefaultPort(address)),
      token_(opts.tokenFile.empty() ? std::string() : readTokenFile(opts.tokenFile)),
      tls_(!opts.tlsCa.empty()),
      channel_(makeChannel(address_, opts)),
      stub_(partita::v1::Partita::NewStub(channel_)) {}

void Connection::fail(const grpc::Status& status, const std::string& what) const {
    // A TLS server closes a plain connection at once: say what probably went wrong.
    if (!tls_ && status.error_code() == grpc::StatusCode::UNAVAILABLE &&
        status.error_message().find("Socket closed") != std::string::npos) {
        grpc::Status hinted(status.error_code(),
                            status.error_message() + " (a TLS server? pass --tls-ca)");
        throwStatus(hinted, what, address_);
    }
    throwStatus(status, what, address_);
}

void Connection::waitForServer(double seconds, bool announce) {
    auto after = [](double s) {
        return std::chrono::system_clock::now() + std::chrono::milliseconds(int64_t(s * 1000));
    };
    if (channel_->WaitForConnected(after(0.25))) return;
    if (announce) {
        std::fprintf(stderr, "partita: waiting for the server at %s (up to %.0f s)...\n",
                     address_.c_str(), seconds);
        std::fflush(stderr);
    }
    channel_->WaitForConnected(after(seconds));
}

void Connection::prepare(grpc::ClientContext& context, double deadlineSeconds) const {
    if (!token_.empty()) context.AddMetadata("authorization", "Bearer " + token_);
    if (deadlineSeconds > 0)
        context.set_deadline(std::chrono::system_clock::now() +
                             std::chrono::milliseconds(int64_t(deadlineSeconds * 1000)));
}

}  // namespace partita::cli
