#include "cli/errors.h"

namespace partita::cli {

std::string statusCodeName(grpc::StatusCode code) {
    switch (code) {
        case grpc::StatusCode::OK:
            return "OK";
        case grpc::StatusCode::CANCELLED:
            return "CANCELLED";
        case grpc::StatusCode::UNKNOWN:
            return "UNKNOWN";
        case grpc::StatusCode::INVALID_ARGUMENT:
            return "INVALID_ARGUMENT";
        case grpc::StatusCode::DEADLINE_EXCEEDED:
            return "DEADLINE_EXCEEDED";
        case grpc::StatusCode::NOT_FOUND:
            return "NOT_FOUND";
        case grpc::StatusCode::ALREADY_EXISTS:
            return "ALREADY_EXISTS";
        case grpc::StatusCode::PERMISSION_DENIED:
            return "PERMISSION_DENIED";
        case grpc::StatusCode::UNAUTHENTICATED:
            return "UNAUTHENTICATED";
        case grpc::StatusCode::RESOURCE_EXHAUSTED:
            return "RESOURCE_EXHAUSTED";
        case grpc::StatusCode::FAILED_PRECONDITION:
            return "FAILED_PRECONDITION";
        case grpc::StatusCode::ABORTED:
            return "ABORTED";
        case grpc::StatusCode::OUT_OF_RANGE:
            return "OUT_OF_RANGE";
        case grpc::StatusCode::UNIMPLEMENTED:
            return "UNIMPLEMENTED";
        case grpc::StatusCode::INTERNAL:
            return "INTERNAL";
        case grpc::StatusCode::UNAVAILABLE:
            return "UNAVAILABLE";
        case grpc::StatusCode::DATA_LOSS:
            return "DATA_LOSS";
        default:
            return "CODE_" + std::to_string(int(code));
    }
}

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
