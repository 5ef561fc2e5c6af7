// The chain runner's halves (issue #26): in the PerGroupWithHalves layout each group's film is
// the PerGroup layout's bit for bit, its odd chains get a combined-only film, and halvesError is
// the error of two halves rendered as groups of their own (the same chains: each chain's
// stream is its own, whatever its group).
#include <gtest/gtest.h>

#include <atomic>

#include "camera.h"
#include "gltf/gltf_loader.h"
#include "half_split_error.h"
#include "image_bits.h"
#include "integrators/mlt/mlt_integrator.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_runner.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "renderer.h"
#include "thread_pool.h"

namespace partita {
namespace {

TEST(ChainHalves, AGroupsOddChainsGiveItsErrorWithoutChangingItsFilm) {
    RenderScene scene(loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf"));
    RenderSettings st;
    st.width = 24;
    st.height = 18;
    st.budget = 8;
    st.budgetKind = BudgetKind::MutationsPerPixel;
    st.seed = 5;
    st.maxDepth = 6;
    st.previewIntervalSeconds = 0;
    Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    MltSettings settings;
    settings.bootstrapSamples = 20000;
    settings.direct = "chains";
    settings.chains = 16;
    const MltStart start = startMlt(ctx, settings);
    ASSERT_EQ(start.plan.groups.size(), 1u);
    // The same chains as two groups of the same b: the even and the odd ones.
    ChainPlan split = start.plan;
    split.groups.push_back(split.groups[0]);
    for (size_t k = 0; k < split.chains.size(); ++k) split.chains[k].group = uint32_t(k % 2);

    auto run = [&](const ChainPlan& plan, ChainRunner::FilmLayout layout) {
        auto runner = std::make_unique<ChainRunner>(
            ctx, plan, [&](uint32_t) { return makeMltMutations(ctx, settings); },
            ChainRunner::RestrictionFactory{}, 1024, layout);
        ProgressReporter progress(observer, "render", "mutations", 0);
        runner->run(progress, 0);
        return runner;
    };
    auto perGroup = run(start.plan, ChainRunner::FilmLayout::PerGroup);
    auto withHalves = run(start.plan, ChainRunner::FilmLayout::PerGroupWithHalves);
    auto asGroups = run(split, ChainRunner::FilmLayout::PerGroup);

    ASSERT_EQ(withHalves->filmCount(), 2u);
    test::expectSameBits(perGroup->film(0).resolve(1.0f, 1024),
                         withHalves->film(0).resolve(1.0f, 1024));
    EXPECT_TRUE(withHalves->film(1).layers().keepsNone());
    EXPECT_EQ(withHalves->film(1).resolveCombined(1.0f).rgb,
              asGroups->film(1).resolveCombined(1.0f).rgb);
    EXPECT_EQ(perGroup->halvesError(0).count, 0.0) << "PerGroup keeps no halves";

    const uint64_t even = asGroups->mutationsDone(0), odd = asGroups->mutationsDone(1);
    ASSERT_GT(even, 0u);
    ASSERT_GT(odd, 0u);
    const double b = start.plan.groups[0].b;
    const ErrorSums expected = halvesError(
        asGroups->film(0).resolveCombined(ChainRunner::filmScale(b, st.width, st.height, even)),
        asGroups->film(1).resolveCombined(ChainRunner::filmScale(b, st.width, st.height, odd)),
        double(even), double(odd));
    const ErrorSums got = withHalves->halvesError(0);
    ASSERT_GT(expected.variance, 0.0);
    EXPECT_NEAR(got.variance, expected.variance, 1e-4 * expected.variance);
    EXPECT_NEAR(got.value, expected.value, 1e-5 * expected.value);
    EXPECT_EQ(got.count, double(st.width) * st.height * 3);
}

TEST(ChainHalves, ARequestedStopEndsTheRunAfterItsRound) {
    RenderScene scene(loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf"));
    RenderSettings st;
    st.width = 16;
    st.height = 12;
    st.budget = 64;
    st.budgetKind = BudgetKind::MutationsPerPixel;
    st.seed = 2;
    st.maxDepth = 6;
    st.previewIntervalSeconds = 0;
    Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    MltSettings settings;
    settings.bootstrapSamples = 20000;
    settings.direct = "chains";
    settings.chains = 8;
    const MltStart start = startMlt(ctx, settings);
    ChainRunner runner(
        ctx, start.plan, [&](uint32_t) { return makeMltMutations(ctx, settings); }, {},
        /*roundMutations=*/16);
    ProgressReporter progress(observer, "render", "mutations", 0);
    int rounds = 0;
    runner.run(progress, 0, [&](double) {
        if (++rounds == 3) runner.requestStop();
    });
    EXPECT_EQ(rounds, 3);
    EXPECT_EQ(runner.mutationsDone(), 3u * 16u * start.plan.chains.size());
    EXPECT_LT(runner.mutationsDone(), start.plan.mutations());
}

}  // namespace
}  // namespace partita
