// The standard gRPC health check (grpc.health.v1.Health/Check) against a partitad.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

namespace partita::cli {

struct HealthResult {
    grpc::Status status;   // the call's status
    bool serving = false;  // answered SERVING
};

/// One Check for the whole server (service ""), with a deadline. `token` may be empty.
HealthResult checkHealth(const std::shared_ptr<grpc::Channel>& channel, const std::string& token,
                         double timeoutSeconds);

}  // namespace partita::cli
