// Logs refused requests (bad input, wrong token, over a limit) with the peer and the method, so
// that an operator sees probing and abuse. Rate-limited: a flood of bad requests costs a few log
// lines per window and one line counting the rest, never a full disk.
#pragma once

#include <grpcpp/support/status.h>

#include <chrono>
#include <mutex>
#include <string>
#include <string_view>

namespace partita::server {

class RejectLog {
  public:
    RejectLog() = default;
    RejectLog(const RejectLog&) = delete;
    RejectLog& operator=(const RejectLog&) = delete;
    /// Flushes: the count of refusals not logged reaches the log at shutdown too.
    ~RejectLog();

    /// Logs `status` when it is INVALID_ARGUMENT, UNAUTHENTICATED or RESOURCE_EXHAUSTED, at most
    /// kLinesPerWindow lines per kWindow.
    void note(std::string_view method, const std::string& peer, const grpc::Status& status);

    /// Logs the count of refusals not logged so far, if any.
    void flush();

    static constexpr int kLinesPerWindow = 20;
    static constexpr std::chrono::seconds kWindow{10};

  private:
    std::mutex mutex_;
    std::chrono::steady_clock::time_point windowStart_{};
    int logged_ = 0;
    long suppressed_ = 0;
};

/// True for the codes RejectLog logs.
bool isRejection(grpc::StatusCode code);

}  // namespace partita::server
