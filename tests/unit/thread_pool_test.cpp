// The core's ThreadPool: every item of a parallel loop runs exactly once, on several threads,
// its writes are visible to the caller when parallelFor returns, exceptions reach the caller,
// and two jobs can share one pool at the same time. make test-tsan runs these under
// ThreadSanitizer.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "thread_pool.h"

namespace partita {
namespace {

/// Item i writes f(i) into its own slot of a plain vector (no atomics: the pool's join must
/// publish the writes).
std::vector<uint64_t> squares(ThreadPool& pool, size_t count) {
    std::vector<uint64_t> out(count, 0);
    pool.parallelFor(count, [&](size_t i) { out[i] = uint64_t(i) * i; });
    return out;
}

TEST(ThreadPool, EveryItemRunsExactlyOnceAndItsWritesAreSeenAfterwards) {
    ThreadPool pool(4);
    std::vector<std::atomic<int>> runs(1000);
    pool.parallelFor(runs.size(), [&](size_t i) { runs[i].fetch_add(1); });
    for (size_t i = 0; i < runs.size(); ++i) ASSERT_EQ(runs[i].load(), 1) << i;
    std::vector<uint64_t> out = squares(pool, 1000);
    for (size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], uint64_t(i) * i) << i;
}

TEST(ThreadPool, ItemsRunOnSeveralThreads) {
    ThreadPool pool(4);
    std::mutex mutex;
    std::set<std::thread::id> threads;
    pool.parallelFor(64, [&](size_t) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        std::lock_guard lock(mutex);
        threads.insert(std::this_thread::get_id());
    });
    EXPECT_GT(threads.size(), 1u);
}

TEST(ThreadPool, AnExceptionOfAnItemReachesTheCaller) {
    ThreadPool pool(4);
    EXPECT_THROW(pool.parallelFor(100,
                                  [](size_t i) {
                                      if (i == 37) throw std::runtime_error("item 37");
                                  }),
                 std::runtime_error);
    // The pool still works afterwards.
    EXPECT_EQ(squares(pool, 10)[9], 81u);
}

TEST(ThreadPool, TwoJobsShareOnePoolAtTheSameTime) {
    ThreadPool pool(4);
    std::vector<uint64_t> a, b;
    std::thread first([&] {
        for (int k = 0; k < 20; ++k) a = squares(pool, 500);
    });
    std::thread second([&] {
        for (int k = 0; k < 20; ++k) b = squares(pool, 300);
    });
    first.join();
    second.join();
    ASSERT_EQ(a.size(), 500u);
    ASSERT_EQ(b.size(), 300u);
    EXPECT_EQ(a[499], 499u * 499u);
    EXPECT_EQ(b[299], 299u * 299u);
}

}  // namespace
}  // namespace partita
