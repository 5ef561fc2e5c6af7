// Messages to and from the wire, for the service's raw (ByteBuffer) methods. The service parses
// requests itself instead of letting gRPC do it: gRPC answers a request it cannot parse (a proto3
// string that is not UTF-8, most often) with a bare UNIMPLEMENTED, while this says which field is
// wrong, as INVALID_ARGUMENT. Every response passes through serialize(), which makes every string
// field valid UTF-8, so no stored or echoed text can make a message that clients fail to parse.
#pragma once

#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

#include <string>

namespace partita::server {

/// Parses a request. INVALID_ARGUMENT naming the field when a string field is not UTF-8, or
/// saying the request is malformed.
grpc::Status parseRequest(const grpc::ByteBuffer& wire, google::protobuf::Message& out);

/// True when every string field, recursively, is valid UTF-8.
bool allStringsValid(const google::protobuf::Message& message);

/// Rewrites every string field (recursively, maps and repeated fields included) that is not
/// valid UTF-8 with its bad bytes escaped (text.h). Bytes fields are left alone.
void makeStringsValidUtf8(google::protobuf::Message& message);

/// makeStringsValidUtf8, then the message's wire form.
grpc::ByteBuffer serialize(google::protobuf::Message& message);

}  // namespace partita::server
