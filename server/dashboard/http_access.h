// Who may use the dashboard, and from where (DESIGN.md "Security"; the gRPC rules, for HTTP):
// - a configured token is required on every request: an `Authorization: Bearer <token>`
//   header, or the `partita_token` cookie a browser gets by opening any page with
//   `?token=<token>` once (HttpOnly, SameSite=Strict, Secure under TLS);
// - on a loopback address the Host header must name a loopback host, so a page elsewhere
//   cannot reach the dashboard through DNS rebinding;
// - requests that change something (POST, DELETE) must carry `X-Partita: 1`: a page of another
//   origin cannot send that header without a CORS preflight, which is never granted.
#pragma once

#include <httplib.h>

#include <string>

#include "auth.h"

namespace partita::server::dashboard {

constexpr const char* kTokenCookie = "partita_token";

class HttpAccess {
  public:
    HttpAccess(const TokenAuth& auth, bool loopback, bool tls)
        : auth_(auth), loopback_(loopback), tls_(tls) {}

    /// OK, or the refusal (UNAUTHENTICATED, PERMISSION_DENIED) saying why.
    grpc::Status check(const httplib::Request& request) const;

    /// The Set-Cookie value that keeps a `?token=` login for the session, or "" when the request
    /// carried no valid token in its query.
    std::string loginCookie(const httplib::Request& request) const;

  private:
    bool tokenAccepted(const httplib::Request& request) const;

    const TokenAuth& auth_;
    const bool loopback_, tls_;
};

/// The value of cookie `name` in a Cookie header ("" when absent).
std::string cookieValue(const std::string& header, const std::string& name);
/// True when the Host header (host or host:port) names localhost, 127.0.0.0/8 or [::1].
bool isLoopbackHost(const std::string& hostHeader);

}  // namespace partita::server::dashboard
