#include "integrators/mlt/mlt_shards.h"

#include <stdexcept>

#include "byte_stream.h"
#include "integrators/mlt/mlt_integrator.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_runner.h"
#include "progress_reporter.h"
#include "shard/chain_shards.h"

namespace partita {

namespace {

struct MltPlan {
    ChainPlan chains;
    uint64_t bootstrapRays = 0;
};

std::vector<uint8_t> serializeMltPlan(const MltPlan& plan) {
    ByteWriter w;
    w.put(plan.bootstrapRays);
    w.putBytes(serializeChainPlan(plan.chains));
    return std::move(w.bytes);
}

MltPlan deserializeMltPlan(std::span<const uint8_t> bytes) {
    ByteReader r(bytes, "mlt plan");
    MltPlan plan;
    plan.bootstrapRays = r.get<uint64_t>();
    plan.chains = deserializeChainPlan(r.getBytes());
    if (plan.chains.groups.size() != 1) r.fail("expected one chain group");
    if (!r.atEnd()) r.fail("trailing bytes");
    return plan;
}

}  // namespace

std::vector<uint8_t> MltShards::plan(const RenderContext& ctx) {
    requireMutationBudget(ctx, "mlt");
    MltStart start = startMlt(ctx, settings_);
    return serializeMltPlan({std::move(start.plan), start.bootstrap.rays});
}

uint32_t MltShards::maxShards(const RenderContext&, std::span<const uint8_t> plan) const {
    return uint32_t(std::max<size_t>(1, deserializeMltPlan(plan).chains.chains.size()));
}

ShardWork MltShards::renderShard(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                 uint32_t shard, uint32_t shards) {
    auto makeMutations = [&](uint32_t) { return makeMltMutations(ctx, settings_); };
    return runChainShard(ctx, deserializeMltPlan(bytes).chains, shard, shards, makeMutations, {},
                         settings_.roundMutations);
}

RenderResult MltShards::resolve(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                const ShardWork& merged) {
    const MltPlan plan = deserializeMltPlan(bytes);
    const RenderSettings& rs = ctx.settings;
    const double b = plan.chains.groups[0].b;
    const Film& film = merged.films.at(0);
    RenderResult result;
    result.image = film.resolve(ChainRunner::filmScale(b, rs.width, rs.height, merged.counts.at(0)),
                                rs.maxTypeLayers, nullptr);
    RenderStats& st = result.stats;
    addMergedChainStats(st, merged, plan.chains, double(rs.width) * rs.height);
    st.values["b"] = b;
    st.values["bootstrap_samples"] = double(plan.chains.bootstrapSamples);
    st.values["path_types"] = double(film.typeCount());
    st.values["rays"] += double(plan.bootstrapRays);
    return result;
}

}  // namespace partita
