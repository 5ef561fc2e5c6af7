// The core's pool of worker threads. Work is expressed as parallel loops over independent items
// (tiles, chains); results never depend on how items land on threads. Several jobs may share one
// pool: each parallelFor call is its own TBB task group inside the pool's arena.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace partita {

class ThreadPool {
  public:
    /// `threads` <= 0 means one per hardware thread.
    explicit ThreadPool(int threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int threadCount() const { return threads_; }
    /// Calls body(i) for every i in [0, count), each exactly once, in parallel; returns when all
    /// are done. Exceptions thrown by body propagate to the caller.
    void parallelFor(size_t count, const std::function<void(size_t)>& body);

  private:
    int threads_;
    struct Arena;
    std::unique_ptr<Arena> arena_;
};

}  // namespace partita
