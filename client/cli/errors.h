// How the CLI fails: every error becomes one line on stderr,
//   partita: error: <message> (<GRPC_CODE>)
// where the code is there when the failure came from the server.
#pragma once

#include <grpcpp/support/status.h>

#include <stdexcept>
#include <string>

#include "status_code_name.h"

namespace partita::cli {

/// A failure the CLI reports and exits on. `code` is the gRPC status code name
/// ("INVALID_ARGUMENT") when a call failed, else empty.
class CliError : public std::runtime_error {
  public:
    explicit CliError(const std::string& message, std::string code = {}, int exitCode = 1)
        : std::runtime_error(message), code_(std::move(code)), exitCode_(exitCode) {}
    const std::string& code() const { return code_; }
    int exitCode() const { return exitCode_; }

  private:
    std::string code_;
    int exitCode_;
};

/// "INVALID_ARGUMENT", "NOT_FOUND", ... (proto/status_code_name.h).
using partita::statusCodeName;

/// Throws a CliError for a failed call: `what` says what was attempted ("submit job"), the
/// server's message follows, the code goes in parentheses. Unreachable servers get a message
/// that says so (naming `address` when given).
[[noreturn]] void throwStatus(const grpc::Status& status, const std::string& what,
                              const std::string& address = {});

/// One line: newlines and trailing whitespace of `s` collapsed to single spaces.
std::string oneLine(const std::string& s);

}  // namespace partita::cli
