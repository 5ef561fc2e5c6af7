// A few threads that run small tasks in submission order per thread: the service uses them to
// prepare and start writes on watch streams (encoding preview PNGs), so that neither render
// threads nor gRPC's own threads do that work.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace partita::server {

class Executor {
  public:
    explicit Executor(int threads);
    ~Executor();  // runs what is queued, then joins
    Executor(const Executor&) = delete;
    Executor& operator=(const Executor&) = delete;

    void post(std::function<void()> task);

  private:
    void loop();
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<std::function<void()>> tasks_;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace partita::server
