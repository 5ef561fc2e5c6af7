// Blocks of samples run in waves: each wave's blocks in parallel on the pool, then merged in
// block order and freed before the next wave starts. The merge order is the block order, so the
// sums are the same for any thread count; and only one wave's partial results are ever alive,
// so that a start-up of 2^20 samples over thousands of path types holds a wave of per-type
// tables, not one per block (issue #25 1: the pre-pass held every block's until the end). A
// `stop` test between waves ends the run early (a time budget's start-up share): the blocks run
// are then a prefix, [0, returned).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "thread_pool.h"

namespace partita {

/// Runs blocks [0, blocks) as described above: run(k, block) fills a fresh Block for block k,
/// merge(block) folds it into the caller's result. Returns how many blocks ran.
template <class Block, class Run, class Merge, class Stop>
uint64_t runInWaves(ThreadPool& pool, uint64_t blocks, Run run, Merge merge, Stop stop) {
    // Enough blocks a wave to keep every thread busy; few enough that a wave is small.
    const uint64_t wave = uint64_t(std::max(16, 4 * pool.threadCount()));
    uint64_t next = 0;
    while (next < blocks) {
        if (next > 0 && stop()) break;  // the first wave always runs
        uint64_t count = std::min(wave, blocks - next);
        std::vector<Block> done(count);
        pool.parallelFor(size_t(count), [&](size_t i) { run(next + i, done[i]); });
        for (Block& block : done) merge(block);
        next += count;
    }
    return next;
}

}  // namespace partita
