#include "thread_pool.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <thread>

namespace partita {

struct ThreadPool::Arena {
    tbb::task_arena arena;
    explicit Arena(int n) : arena(n) {}
};

ThreadPool::ThreadPool(int threads)
    : threads_(threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()))),
      arena_(std::make_unique<Arena>(threads_)) {}

ThreadPool::~ThreadPool() = default;

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

}  // namespace partita
