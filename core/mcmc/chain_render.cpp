#include "mcmc/chain_render.h"

#include <algorithm>

#include "clock.h"
#include "path/path.h"
#include "preview_schedule.h"
#include "progress_reporter.h"
#include "thread_pool.h"

namespace partita {

void runChainsWithPreviews(const RenderContext& ctx, ChainRunner& runner, const ChainPlan& plan,
                           double startupSeconds,
                           const std::function<LayeredImage(ThreadPool*)>& resolve,
                           const std::function<void(RenderStats&)>& addStats,
                           const std::function<void(ProgressReporter&)>& publish) {
    const RenderSettings& rs = ctx.settings;
    bool timed = rs.budgetKind == BudgetKind::Seconds;
    // A start-up that used the whole time budget still leaves one short round (an image); 0
    // would mean "no time limit" to the runner.
    double seconds = timed ? std::max(1e-3, rs.budget - startupSeconds) : 0;
    ProgressReporter progress(ctx.observer, "render", "mutations",
                              timed ? 0 : double(plan.mutations()), seconds);
    PreviewSchedule previews(ctx);
    auto afterRound = [&](double elapsed) {
        if (publish) publish(progress);
        if (!previews.due()) return;
        const auto began = Clock::now();
        RenderStats st;
        st.values["mutations"] = double(runner.mutationsDone());
        st.values["seconds"] = elapsed + startupSeconds;
        if (addStats) addStats(st);
        ctx.observer.onPreview(resolve(&ctx.pool), st);
        previews.shown(began);
    };
    runner.run(progress, seconds, afterRound);
    progress.flush();
}

std::vector<uint8_t> chainStart(const RenderContext& ctx, const BootstrapSampler& sampler,
                                const std::vector<BootstrapCandidate>& candidates, size_t first,
                                const PathRestriction& accept) {
    uint64_t rays = 0;
    for (size_t c = first; c < candidates.size(); ++c) {
        if (accept && !accept(candidates[c].type)) continue;  // not worth regenerating
        MarkovPath path;
        if (!sampler.regenerate(candidates[c], path, rays)) continue;
        std::vector<uint8_t> bytes = serializePath(path.vertices);
        // The chain will start from the rebuilt path (chain_runner.h), so that is what counts.
        MarkovPath rebuilt;
        rebuilt.vertices = deserializePath(ctx.scene, ctx.camera, bytes);
        if (!evaluatePath(ctx.scene, ctx.camera, rebuilt)) continue;
        if (accept && !accept(rebuilt.type)) continue;
        return bytes;
    }
    return {};
}

void addChainStats(RenderStats& st, const ChainRunner& runner, const ChainPlan& plan,
                   double seconds, double startupSeconds, uint64_t startupRays, double pixels) {
    double done = double(runner.mutationsDone());
    double renderSeconds = seconds - startupSeconds;
    st.values["chains"] = double(plan.chains.size());
    st.values["mutations"] = done;
    st.values["mpp"] = done / pixels;
    st.values["seconds"] = seconds;
    st.values["render_seconds"] = renderSeconds;
    st.values["mutations_per_second"] = renderSeconds > 0 ? done / renderSeconds : 0;
    double rays = double(runner.rays() + startupRays);
    st.values["rays"] = rays;
    st.values["rays_per_second"] = seconds > 0 ? rays / seconds : 0;
    // The mean burn-in steps a chain ran (startup_rule.h).
    st.values["burn_in_steps"] = double(runner.burnInSteps());
    st.values["burn_in"] =
        plan.chains.empty() ? 0 : double(runner.burnInSteps()) / double(plan.chains.size());
    st.values["stuck_chains"] = double(runner.stuckChains());
    st.values["type_bound_chains"] = double(runner.typeBoundChains());
    for (const auto& [name, m] : runner.mutationStats()) {
        st.values["proposed_" + name] = double(m.proposed);
        st.values["acceptance_" + name] = m.proposed ? double(m.accepted) / double(m.proposed) : 0;
    }
}

}  // namespace partita
