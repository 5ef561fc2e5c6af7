// Who may call: an optional shared token that every request carries as the metadata entry
// `authorization: Bearer <token>`, compared in constant time. (Transport security, TLS, is set up
// in main.cpp from --tls-cert/--tls-key.)
#pragma once

#include <grpcpp/grpcpp.h>

#include <filesystem>
#include <string>
#include <string_view>

namespace partita::server {

/// Equal contents, in time that depends only on the length of `expected`.
bool constantTimeEquals(std::string_view given, std::string_view expected);

class TokenAuth {
  public:
    TokenAuth() = default;  // no token: every caller is accepted
    explicit TokenAuth(std::string token) : token_(std::move(token)) {}

    /// Reads the token from a file (surrounding whitespace ignored). Throws std::runtime_error
    /// when the file cannot be read or holds no token.
    static TokenAuth fromFile(const std::filesystem::path& file);

    bool enabled() const { return !token_.empty(); }
    /// OK, or UNAUTHENTICATED saying what is missing. Never echoes the token.
    grpc::Status check(const grpc::ServerContextBase& context) const;
    /// The same check of an authorization value ("Bearer <token>") that came another way (the
    /// dashboard's HTTP header).
    grpc::Status checkAuthorization(std::string_view value) const;
    /// Whether `given` is the token (constant time): the dashboard's cookie carries it bare.
    bool matches(std::string_view given) const {
        return enabled() && constantTimeEquals(given, token_);
    }

  private:
    std::string token_;
};

}  // namespace partita::server
