#include "cli/health.h"

#include <chrono>

#include "health.grpc.pb.h"

namespace partita::cli {

HealthResult checkHealth(const std::shared_ptr<grpc::Channel>& channel, const std::string& token,
                         double timeoutSeconds) {
    auto stub = grpc::health::v1::Health::NewStub(channel);
    grpc::ClientContext context;
    if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
    context.set_deadline(std::chrono::system_clock::now() +
                         std::chrono::milliseconds(int64_t(timeoutSeconds * 1000)));
    grpc::health::v1::HealthCheckRequest request;
    grpc::health::v1::HealthCheckResponse response;
    HealthResult result;
    result.status = stub->Check(&context, request, &response);
    result.serving =
        result.status.ok() && response.status() == grpc::health::v1::HealthCheckResponse::SERVING;
    return result;
}

}  // namespace partita::cli
