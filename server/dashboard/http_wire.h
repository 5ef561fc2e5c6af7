// The dashboard's wire: protobuf messages as JSON (proto3's JSON mapping, field names as in the
// .proto), and gRPC status codes as HTTP ones, so the HTTP API says what the gRPC API says.
#pragma once

#include <google/protobuf/message.h>
#include <grpcpp/support/status.h>

#include <string>

namespace partita::server::dashboard {

/// The message as compact JSON on one line (no newline: it can be an SSE data line). Strings
/// that are not valid UTF-8 are escaped first (wire.h), so the JSON always parses.
std::string toJson(google::protobuf::Message& message);

/// Parses JSON into `out`. INVALID_ARGUMENT saying what is wrong (unknown field, bad value).
grpc::Status fromJson(const std::string& json, google::protobuf::Message& out);

/// The HTTP status of a gRPC status code (INVALID_ARGUMENT 400, NOT_FOUND 404, ...).
int httpStatus(grpc::StatusCode code);

/// {"code":"NOT_FOUND","error":"<message>"}: the body of every refused request.
std::string errorJson(const grpc::Status& status);

}  // namespace partita::server::dashboard
