// The chain plan: everything the chains of an MCMC render need, as data (DESIGN.md,
// "Scale-out"). Groups hold a normalising constant each (mlt: one group, b; partitioned: one
// per partition, b_i); each chain names its group, its initial path (serialised, path.h), its
// random stream and its number of mutations. Given the plan, chain k's result depends only on
// k, so images do not depend on the thread count, and a chain can run in another process.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "type_layers.h"

namespace partita {

struct ChainGroup {
    std::string label;  // "all" for mlt; the partition's type string for partitioned
    double b = 0;       // the integral of f* over the group's part of path space
};

struct PlannedChain {
    uint32_t group = 0;
    uint64_t stream = 0;  // the chain's Rng is Rng(plan.seed, stream)
    uint64_t mutations = 0;
    uint64_t burnIn = 0;         // steps run before the first splat (not in `mutations`)
    std::vector<uint8_t> start;  // serializePath of the initial path
};

struct ChainPlan {
    uint64_t seed = 0;
    uint64_t bootstrapSamples = 0;
    std::vector<ChainGroup> groups;
    std::vector<PlannedChain> chains;
    /// The types every group's film keeps a layer of (type_layers.h): mlt's largest types of the
    /// bootstrap, none for the partitions (their images are combined ones).
    TypeLayers layers = TypeLayers::every();

    /// Mutations of all the chains of group g (of every group when g < 0).
    uint64_t mutations(int group = -1) const;
};

/// A versioned binary form; deserializeChainPlan throws std::invalid_argument for anything
/// else (truncated, another version, garbage).
std::vector<uint8_t> serializeChainPlan(const ChainPlan& plan);
ChainPlan deserializeChainPlan(std::span<const uint8_t> bytes);

}  // namespace partita
