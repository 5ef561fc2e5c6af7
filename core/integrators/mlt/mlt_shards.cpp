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
    // Direct light per pixel: the chains are restricted to the other paths, and the shards
    // share the direct light's samples per pixel (each a range of sample indices).
    bool directApart = false;
    uint64_t directSpp = 0;
    double bDirect = 0;
};

std::vector<uint8_t> serializeMltPlan(const MltPlan& plan) {
    ByteWriter w;
    w.put(plan.bootstrapRays);
    w.putBytes(serializeChainPlan(plan.chains));
    w.put(uint8_t(plan.directApart));
    w.put(plan.directSpp);
    w.put(plan.bDirect);
    return std::move(w.bytes);
}

MltPlan deserializeMltPlan(std::span<const uint8_t> bytes) {
    ByteReader r(bytes, "mlt plan");
    MltPlan plan;
    plan.bootstrapRays = r.get<uint64_t>();
    plan.chains = deserializeChainPlan(r.getBytes());
    if (plan.chains.groups.size() != 1) r.fail("expected one chain group");
    plan.directApart = r.get<uint8_t>() != 0;
    plan.directSpp = r.get<uint64_t>();
    plan.bDirect = r.get<double>();
    if (!r.atEnd()) r.fail("trailing bytes");
    return plan;
}

}  // namespace

std::vector<uint8_t> MltShards::plan(const RenderContext& ctx) {
    requireMutationBudget(ctx, "mlt");
    MltStart start = startMlt(ctx, settings_);
    return serializeMltPlan({std::move(start.plan), start.bootstrap.rays, start.directApart,
                             start.directSpp, start.bDirect});
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
    ShardWork work = runChainShard(ctx, plan.chains, shard, shards, makeMutations, restrictions,
                                   settings_.roundMutations);
    if (!plan.directApart) return work;
    // The direct light's film after the chains' one, with its samples per pixel as its count:
    // every (pixel, sample) has its own stream and the film sums exactly, so the merged film
    // is the one-process render's.
    const ShareRange share = shareRange(plan.directSpp, shards, shard);
    DirectLightRenderer direct(ctx);
    if (share.count() > 0) {
        const double pixels = double(ctx.settings.width) * ctx.settings.height;
        ProgressReporter progress(ctx.observer, "render", "samples",
                                  pixels * double(share.count()));
        direct.renderPass({share.first, share.end}, &progress);
        progress.flush();
    }
    work.sums["direct_rays"] = double(direct.rays());
    work.films.push_back(direct.takeFilm());
    work.counts.push_back(share.count());
    return work;
}

RenderResult MltShards::resolve(const RenderContext& ctx, std::span<const uint8_t> bytes,
                                const ShardWork& merged) {
    const MltPlan plan = deserializeMltPlan(bytes);
    const RenderSettings& rs = ctx.settings;
    const double b = plan.chains.groups[0].b;
    const Film& film = merged.films.at(0);
    const size_t films = plan.directApart ? 2 : 1;
    if (merged.films.size() != films || merged.counts.size() != films)
        throw std::invalid_argument("merged mlt work has " + std::to_string(merged.films.size()) +
                                    " films, expected " + std::to_string(films));
    RenderResult result;
    result.image = film.resolve(ChainRunner::filmScale(b, rs.width, rs.height, merged.counts.at(0)),
                                rs.maxTypeLayers, nullptr);
    RenderStats& st = result.stats;
    // The chains' statistics from the chains' film and count only.
    ShardWork chains;
    chains.counts = {merged.counts[0]};
    chains.sums = merged.sums;
    addMergedChainStats(st, chains, plan.chains, double(rs.width) * rs.height);
    st.values["b"] = b;
    st.values["bootstrap_samples"] = double(plan.chains.bootstrapSamples);
    st.values["path_types"] = double(film.typeCount());
    st.values["rays"] += double(plan.bootstrapRays);
    const double chainRays = st.values["rays"];
    double directRays = 0;
    if (plan.directApart) {
        const Film& directFilm = merged.films[1];
        result.image = addDisjointParts(
            resolveDirectLight(directFilm, merged.counts[1], rs.maxTypeLayers, nullptr),
            result.image, rs.maxTypeLayers);
        directRays = st.values["direct_rays"];
        st.values["rays"] += directRays;
        st.values["path_types"] += double(directFilm.typeCount());
    }
    addDirectLightStats(st, plan.directApart, plan.directApart ? merged.counts[1] : 0, plan.bDirect,
                        directRays, chainRays - double(plan.bootstrapRays));
    return result;
}

}  // namespace partita
