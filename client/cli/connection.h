// A connection to a partitad: the channel (plain on loopback, TLS with --tls-ca), the bearer
// token from --token-file sent with every call, and helpers that turn failed calls into
// CliErrors.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "cli/errors.h"
#include "cli/proto.h"

namespace partita::cli {

/// The global options that say how to reach a server.
struct ServerOptions {
    std::string server;         // HOST:PORT; empty = start a private daemon
    std::string tokenFile;      // bearer token, sent as "authorization: Bearer <token>"
    std::string tlsCa;          // PEM roots; set = TLS
    std::string tlsServerName;  // override of the name checked in the server's certificate
};

/// Reads a token file: the first line, surrounding whitespace removed. Throws CliError when it
/// is missing or empty.
std::string readTokenFile(const std::string& path);

/// partitad's default port, used when --server names only a host.
constexpr int kDefaultPort = 50051;

/// "HOST" and "[v6]" get ":50051"; "HOST:PORT", "[v6]:PORT", "unix:..." and URIs stay as they
/// are (without this, gRPC dials "localhost" on port 443).
std::string withDefaultPort(const std::string& address);

/// "localhost:PORT" becomes "127.0.0.1:PORT" (RFC 6761: localhost is the loopback), anything
/// else stays. gRPC's default resolver (c-ares) asks DNS servers for "localhost" when /etc/hosts
/// lacks it, as in a minimal container, and fails where there are none; partitad listens on
/// 127.0.0.1 by default. With TLS the certificate is still checked for "localhost".
std::string loopbackForLocalhost(const std::string& address);

std::shared_ptr<grpc::Channel> makeChannel(const std::string& address, const ServerOptions& opts);

class Connection {
  public:
    using Stub = partita::v1::Partita::Stub;

    /// `address` HOST:PORT. Reads the token and CA files now (so a bad path fails early).
    Connection(const std::string& address, const ServerOptions& opts);

    const std::string& address() const { return address_; }
    const std::shared_ptr<grpc::Channel>& channel() const { return channel_; }
    Stub& stub() { return *stub_; }

    /// Waits (at most `seconds`) until the channel is connected, saying on stderr that it waits
    /// when the server does not answer at once (a daemon started a moment ago with '&' is not
    /// listening yet). Returns without error either way: the first call reports the failure.
    void waitForServer(double seconds, bool announce);

    /// Adds the token and, when deadlineSeconds > 0, a deadline.
    void prepare(grpc::ClientContext& context, double deadlineSeconds = 0) const;

    /// A unary call with a deadline; a failure throws CliError("<what>: <message>", code).
    template <class Req, class Resp>
    Resp call(grpc::Status (Stub::*method)(grpc::ClientContext*, const Req&, Resp*),
              const Req& request, const std::string& what, double deadlineSeconds = 60) {
        grpc::ClientContext context;
        prepare(context, deadlineSeconds);
        Resp response;
        grpc::Status status = ((*stub_).*method)(&context, request, &response);
        if (!status.ok()) fail(status, what);
        return response;
    }

    /// throwStatus with this connection's address.
    [[noreturn]] void fail(const grpc::Status& status, const std::string& what) const;

  private:
    std::string address_, token_;
    bool tls_ = false;
    std::shared_ptr<grpc::Channel> channel_;
    std::unique_ptr<Stub> stub_;
};

}  // namespace partita::cli
