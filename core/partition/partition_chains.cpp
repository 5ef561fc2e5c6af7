#include "partition/partition_chains.h"

#include <algorithm>

#include "mcmc/bootstrap.h"
#include "mcmc/chain_render.h"
#include "mcmc/startup_rule.h"
#include "rng.h"
#include "share_range.h"

namespace partita {

namespace {

constexpr uint64_t kResampleStream = 0x50525350ull;        // "PRSP"
constexpr uint64_t kChainStreams = 0x5041525443ull << 24;  // "PARTC"

/// The indices of half B's candidates that belong to partition p (4 bytes a record instead of a
/// copy of its 40: the complement's may hold most of the pre-pass's records).
std::vector<uint32_t> candidatesOf(const PrepassResult& prepass, const Partition& p) {
    std::vector<uint32_t> out;
    for (size_t i = 0; i < prepass.candidatesB.size(); ++i)
        if (p.holds(prepass.candidatesB[i].type)) out.push_back(uint32_t(i));
    return out;
}

}  // namespace

ChainPlan planPartitionChains(const RenderContext& ctx, const BootstrapSampler& sampler,
                              const PrepassResult& prepass,
                              const std::vector<Partition>& partitions,
                              const std::vector<uint64_t>& mutations,
                              const PartitionPipelineSettings& s, uint64_t salt) {
    ChainPlan plan;
    plan.seed = ctx.settings.seed;
    plan.bootstrapSamples = prepass.samplesA + prepass.samplesB;
    plan.layers = TypeLayers::of({});  // partition images are combined ones: no type layers
    uint64_t total = 0;
    for (uint64_t m : mutations) total += m;
    uint64_t stream = kChainStreams + (salt << 40);
    for (size_t g = 0; g < partitions.size(); ++g) {
        plan.groups.push_back({partitions[g].label, partitions[g].b});
        if (mutations[g] == 0) continue;
        double share = double(mutations[g]) / double(std::max<uint64_t>(1, total));
        uint64_t byShare = uint64_t(std::llround(share * double(s.chains)));
        // At least two where the mutations allow: the error estimate's two halves (issue #26,
        // partition_error.h).
        const uint64_t most = std::max<uint64_t>(1, mutations[g] / s.minMutationsPerChain);
        uint64_t chains = std::clamp<uint64_t>(byShare, std::min<uint64_t>(2, most), most);
        std::vector<uint32_t> members = candidatesOf(prepass, partitions[g]);
        Rng rng(ctx.settings.seed, kResampleStream + g + (salt << 32));
        std::vector<size_t> starts =
            resampleCandidates(prepass.candidatesB, members, size_t(chains), rng);
        const Partition& partition = partitions[g];
        for (size_t k = 0; k < starts.size(); ++k) {
            // From the drawn record on, the partition's records in the same order as a copy of
            // them would hold (the others fail `accept`).
            std::vector<uint8_t> start =
                chainStart(ctx, sampler, prepass.candidatesB, members[starts[k]],
                           [&](const PathType& t) { return partition.holds(t); });
            if (start.empty()) continue;
            PlannedChain chain;
            chain.group = uint32_t(g);
            chain.stream = stream++;
            chain.mutations = shareRange(mutations[g], starts.size(), k).count();
            chain.burnIn = StartupRule::burnIn(s.burnIn, chain.mutations, ctx.settings);
            chain.start = std::move(start);
            plan.chains.push_back(std::move(chain));
        }
    }
    return plan;
}

}  // namespace partita
