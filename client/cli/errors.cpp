#include "cli/errors.h"

namespace partita::cli {

std::string oneLine(const std::string& s) {
    std::string out;
    bool space = false;
    for (char c : s) {
        if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
            space = !out.empty();
            continue;
        }
        if (space) out += ' ';
        space = false;
        // Other control characters (terminal escapes in a server's message) print as '?'.
        out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
    }
    return out;
}

void throwStatus(const grpc::Status& status, const std::string& what, const std::string& address) {
    std::string message = oneLine(status.error_message());
    if (status.error_code() == grpc::StatusCode::UNAVAILABLE) {
        std::string head = "cannot reach the server";
        if (!address.empty()) head += " at " + address;
        if (!message.empty()) head += ": " + message;
        message = head;
    } else if (status.error_code() == grpc::StatusCode::UNAUTHENTICATED && message.empty())
        message = "missing or wrong token (see --token-file)";
    if (message.empty()) message = "the call failed";
    throw CliError(what.empty() ? message : what + ": " + message,
                   statusCodeName(status.error_code()));
}

}  // namespace partita::cli
