#include "thread_pool.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

// ThreadSanitizer cannot see the hand-offs inside libtbb (not instrumented): it reports TBB's
// own task set-up as races. Under TSan (make test-tsan) parallelFor runs the same items on
// plain std::threads instead, so that TSan checks the loop bodies, which are ours.
#if defined(__SANITIZE_THREAD__)
#define PARTITA_PLAIN_THREADS 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PARTITA_PLAIN_THREADS 1
#endif
#endif

namespace partita {

struct ThreadPool::Arena {
    tbb::task_arena arena;
    explicit Arena(int n) : arena(n) {}
};

ThreadPool::ThreadPool(int threads)
    : threads_(threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()))),
      arena_(std::make_unique<Arena>(threads_)) {}

ThreadPool::~ThreadPool() = default;

#ifdef PARTITA_PLAIN_THREADS

void ThreadPool::parallelFor(size_t count, const std::function<void(size_t)>& body) {
    std::atomic<size_t> next{0};
    std::mutex mutex;
    std::exception_ptr error;
    auto work = [&] {
        for (size_t i; (i = next.fetch_add(1)) < count;) {
            try {
                body(i);
            } catch (...) {
                std::lock_guard lock(mutex);
                if (!error) error = std::current_exception();
            }
        }
    };
    std::vector<std::thread> threads;
    const size_t n = std::min(count, size_t(threads_));
    for (size_t t = 1; t < n; ++t) threads.emplace_back(work);
    work();
    for (std::thread& t : threads) t.join();
    if (error) std::rethrow_exception(error);
}

#else

void ThreadPool::parallelFor(size_t count, const std::function<void(size_t)>& body) {
    arena_->arena.execute([&] {
        // One item per task: items are coarse (a tile, a chain), so balance beats overhead.
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, count, 1),
            [&](const tbb::blocked_range<size_t>& r) {
                for (size_t i = r.begin(); i != r.end(); ++i) body(i);
            },
            tbb::simple_partitioner());
    });
}

#endif

}  // namespace partita
