#include "reject_log.h"

#include <spdlog/spdlog.h>

#include "status_code_name.h"
#include "text.h"

namespace partita::server {

bool isRejection(grpc::StatusCode code) {
    return code == grpc::StatusCode::INVALID_ARGUMENT ||
           code == grpc::StatusCode::UNAUTHENTICATED ||
           code == grpc::StatusCode::RESOURCE_EXHAUSTED;
}

namespace {

void logSuppressed(long dropped) {
    spdlog::warn("{} more rejected requests were not logged (at most {} lines per {} s)", dropped,
                 RejectLog::kLinesPerWindow, RejectLog::kWindow.count());
}

}  // namespace

RejectLog::~RejectLog() { flush(); }

void RejectLog::flush() {
    long dropped = 0;
    {
        std::lock_guard lock(mutex_);
        std::swap(dropped, suppressed_);
    }
    if (dropped > 0) logSuppressed(dropped);
}

void RejectLog::note(std::string_view method, const std::string& peer, const grpc::Status& status) {
    if (!isRejection(status.error_code())) return;
    long dropped = 0;
    {
        std::lock_guard lock(mutex_);
        auto now = std::chrono::steady_clock::now();
        if (now - windowStart_ >= kWindow) {
            dropped = suppressed_;
            windowStart_ = now;
            logged_ = 0;
            suppressed_ = 0;
        }
        if (logged_ >= kLinesPerWindow) {
            ++suppressed_;
            return;
        }
        ++logged_;
    }
    if (dropped > 0) logSuppressed(dropped);
    spdlog::warn("rejected {} from {}: {}: {}", method, quoteInput(peer, 100),
                 statusCodeName(status.error_code()), quoteInput(status.error_message(), 200));
}

}  // namespace partita::server
