#include "integrators/mlt/mlt_shards.h"

#include <stdexcept>

#include "byte_stream.h"
#include "integrators/mlt/direct_light.h"
#include "integrators/mlt/mlt_integrator.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_runner.h"
#include "progress_reporter.h"
#include "shard/chain_shards.h"
#include "share_range.h"

namespace partita {

namespace {

struct MltPlan {
    ChainPlan chains;
    uint64_t bootstrapRays = 0;
    // Direct light per pixel: the chains, in two halves, are restricted to the other paths;
    // the direct light is rendered when they are done, in the resolve step (its samples per
    // pixel follow from the chains' error and rays), as the one-process render does.
    bool directApart = false;
    double bDirect = 0;
};

std::vector<uint8_t> serializeMltPlan(const MltPlan& plan) {
    ByteWriter w;
    w.put(plan.bootstrapRays);
    w.putBytes(serializeChainPlan(plan.chains));
    // 0: the chains alone; 2: the direct light apart, the chains' films in the runner's
    // AllAndHalf layout (1 was two layered halves, which this build's shards do not make).
    w.put(uint8_t(plan.directApart ? 2 : 0));
    w.put(plan.bDirect);
    return std::move(w.bytes);
}

MltPlan deserializeMltPlan(std::span<const uint8_t> bytes) {
    ByteReader r(bytes, "mlt plan");
    MltPlan plan;
    plan.bootstrapRays = r.get<uint64_t>();
    plan.chains = deserializeChainPlan(r.getBytes());
    const uint8_t direct = r.get<uint8_t>();
    if (direct == 1) r.fail("a plan of an older build (its chain halves in two layered films)");
    if (direct > 2) r.fail("unknown direct-light mode " + std::to_string(direct));
    plan.directApart = direct == 2;
    plan.bDirect = r.get<double>();
    if (plan.chains.groups.size() != (plan.directApart ? 2u : 1u))
        r.fail("expected one chain group, or two with the direct light apart");
    if (!r.atEnd()) r.fail("trailing bytes");
    return plan;
}

}  // namespace

std::vector<uint8_t> MltShards::plan(const RenderContext& ctx) {
    requireMutationBudget(ctx, "mlt");
    if (settings_.targetError > 0)
        throw std::invalid_argument(
            "a sharded mlt job renders its whole budget: leave target_error at 0");
    MltStart start = startMlt(ctx, settings_);
    return serializeMltPlan(
        {std::move(start.plan), start.bootstrap.rays, start.directApart, start.bDirect});
}

uint32_t MltShards::maxShards(const RenderContext&, std::span<const uint8_t> plan) const {
    return uint32_t(std::max<size_t>(1, deserializeMltPlan(plan).chains.chains.size()));
}

ShardWork MltShards::renderShard(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                 uint32_t shard, uint32_t shards) {
    const MltPlan plan = deserializeMltPlan(bytes);
    auto makeMutations = [&](uint32_t) { return makeMltMutations(ctx, settings_); };
    ChainRunner::RestrictionFactory restrictions;
    if (plan.directApart) restrictions = [](uint32_t) { return indirectLightOnly(); };
    return runChainShard(ctx, plan.chains, shard, shards, makeMutations, restrictions,
                         settings_.roundMutations, mltFilmLayout(plan.directApart));
}

RenderResult MltShards::resolve(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                const ShardWork& merged) {
    const MltPlan plan = deserializeMltPlan(bytes);
    const RenderSettings& rs = ctx.settings;
    const double b = plan.chains.groups[0].b;
    const size_t films = plan.chains.groups.size();
    if (merged.films.size() != films || merged.counts.size() != films)
        throw std::invalid_argument("merged mlt work has " + std::to_string(merged.films.size()) +
                                    " films, expected " + std::to_string(films));
    if (plan.directApart && !merged.films[1].layers().keepsNone())
        throw std::invalid_argument("merged mlt work: the odd chains' film has type layers");
    const double pixels = double(rs.width) * rs.height;
    RenderResult result;
    RenderStats& st = result.stats;
    addMergedChainStats(st, merged, plan.chains, pixels);
    st.values["b"] = b;
    st.values["bootstrap_samples"] = double(plan.chains.bootstrapSamples);
    st.values["bootstrap_rays"] = double(plan.bootstrapRays);
    const double chainRays = st.values["rays"];
    st.values["rays"] += double(plan.bootstrapRays);
    if (!plan.directApart) {
        const Film& film = merged.films[0];
        result.image =
            film.resolve(ChainRunner::filmScale(b, rs.width, rs.height, merged.counts[0]),
                         rs.maxTypeLayers, nullptr);
        st.values["path_types"] = double(film.typeCount());
        addDirectLightStats(st, false, {}, 0, chainRays);
        return result;
    }
    // The direct light after the chains, as the one-process render: the same rule on the same
    // films and rays, so the same samples per pixel and film.
    const ChainHalves halves{
        &merged.films[0], &merged.films[1], {merged.counts[0], merged.counts[1]}, b};
    const DirectLightRun direct = directLightAfterChains(
        ctx, settings_, chainsForDirect(settings_, halves, rs), chainRays, nullptr);
    result.image = addDisjointParts(
        resolveDirectLight(direct.renderer->film(), direct.spp, rs.maxTypeLayers, nullptr),
        resolveChainHalves(halves, rs, nullptr), rs.maxTypeLayers);
    st.values["path_types"] =
        double(merged.films[0].typeCount() + direct.renderer->film().typeCount());
    st.values["rays"] += direct.rays();
    addDirectLightStats(st, true, direct, plan.bDirect, chainRays);
    return result;
}

}  // namespace partita
