#include "http_wire.h"

#include <google/protobuf/util/json_util.h>

#include "status_code_name.h"
#include "text.h"
#include "wire.h"

namespace partita::server::dashboard {

namespace {

/// A JSON string literal of UTF-8 text.
std::string jsonString(const std::string& text) {
    std::string out = "\"";
    for (unsigned char c : text) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += char(c);
        } else if (c < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += char(c);
        }
    }
    return out + "\"";
}

}  // namespace

std::string toJson(google::protobuf::Message& message) {
    makeStringsValidUtf8(message);
    google::protobuf::util::JsonPrintOptions options;
    options.preserve_proto_field_names = true;
    options.add_whitespace = false;
    std::string json;
    auto status = google::protobuf::util::MessageToJsonString(message, &json, options);
    if (!status.ok())  // cannot happen with valid UTF-8; never send half a document
        return "{}";
    return json;
}

grpc::Status fromJson(const std::string& json, google::protobuf::Message& out) {
    if (!isValidUtf8(json)) return {grpc::StatusCode::INVALID_ARGUMENT, "the body is not UTF-8"};
    google::protobuf::util::JsonParseOptions options;
    options.ignore_unknown_fields = false;
    auto status = google::protobuf::util::JsonStringToMessage(json, &out, options);
    if (!status.ok())
        return {grpc::StatusCode::INVALID_ARGUMENT,
                "malformed request: " + quoteInput(std::string(status.message()), 200)};
    return grpc::Status::OK;
}

int httpStatus(grpc::StatusCode code) {
    switch (code) {
        case grpc::StatusCode::OK:
            return 200;
        case grpc::StatusCode::INVALID_ARGUMENT:
        case grpc::StatusCode::OUT_OF_RANGE:
            return 400;
        case grpc::StatusCode::UNAUTHENTICATED:
            return 401;
        case grpc::StatusCode::PERMISSION_DENIED:
            return 403;
        case grpc::StatusCode::NOT_FOUND:
            return 404;
        case grpc::StatusCode::ALREADY_EXISTS:
        case grpc::StatusCode::FAILED_PRECONDITION:
        case grpc::StatusCode::ABORTED:
            return 409;
        case grpc::StatusCode::RESOURCE_EXHAUSTED:
            return 429;
        case grpc::StatusCode::CANCELLED:
            return 499;
        case grpc::StatusCode::UNIMPLEMENTED:
            return 501;
        case grpc::StatusCode::UNAVAILABLE:
            return 503;
        case grpc::StatusCode::DEADLINE_EXCEEDED:
            return 504;
        default:
            return 500;
    }
}

std::string errorJson(const grpc::Status& status) {
    return "{\"code\":\"" + statusCodeName(status.error_code()) +
           "\",\"error\":" + jsonString(toValidUtf8(status.error_message())) + "}";
}

}  // namespace partita::server::dashboard
