// The name of a gRPC status code as the protocol spells it ("NOT_FOUND"), for messages, logs
// and the dashboard's JSON errors: one table for the daemon and the clients.
#pragma once

#include <grpcpp/support/status.h>

#include <string>

namespace partita {

/// "INVALID_ARGUMENT", ...; "CODE_<n>" for a number that is no code.
std::string statusCodeName(grpc::StatusCode code);

}  // namespace partita
