// The chain runner's halves (issue #26): in the PerGroupWithHalves layout each group's film is
// the PerGroup layout's bit for bit, its odd chains get a combined-only film, and halvesError is
// the error of two halves rendered as groups of their own (the same chains: each chain's
// stream is its own, whatever its group). And a requested stop ends a run after its round.
#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "half_split_error.h"
#include "image_bits.h"
#include "integrators/mlt/mlt_integrator.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_runner.h"
#include "progress_reporter.h"
#include "render_helpers.h"

namespace partita {
namespace {

/// mlt's start-up on cornell with every path in its chains (one group of `chains` chains) at
/// `mpp` mutations per pixel.
struct MltChains {
    MltChains(int width, int height, double mpp, uint64_t seed, int chains)
        : scene(loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf")),
          render(scene, settingsOf(width, height, mpp, seed)) {
        settings.bootstrapSamples = 20000;
        settings.direct = "chains";
        settings.chains = chains;
        start = startMlt(render.ctx, settings);
    }

    static RenderSettings settingsOf(int width, int height, double mpp, uint64_t seed) {
        RenderSettings st;
        st.width = width;
        st.height = height;
        st.budget = mpp;
        st.budgetKind = BudgetKind::MutationsPerPixel;
        st.seed = seed;
        st.maxDepth = 6;
        st.previewIntervalSeconds = 0;
        return st;
    }

    /// A runner of `plan` with mlt's mutations and rounds of `roundMutations`.
    std::unique_ptr<ChainRunner> runner(
        const ChainPlan& plan, ChainRunner::FilmLayout layout = ChainRunner::FilmLayout::PerGroup,
        uint64_t roundMutations = 1024) {
        return std::make_unique<ChainRunner>(
            render.ctx, plan, [this](uint32_t) { return makeMltMutations(render.ctx, settings); },
            ChainRunner::RestrictionFactory{}, roundMutations, layout);
    }

    RenderScene scene;
    test::TestRenderContext render;
    MltSettings settings;
    MltStart start;
};

TEST(ChainHalves, AGroupsOddChainsGiveItsErrorWithoutChangingItsFilm) {
    MltChains mlt(24, 18, 8, 5, 16);
    const RenderSettings& st = mlt.render.settings;
    ASSERT_EQ(mlt.start.plan.groups.size(), 1u);
    // The same chains as two groups of the same b: the even and the odd ones.
    ChainPlan split = mlt.start.plan;
    split.groups.push_back(split.groups[0]);
    for (size_t k = 0; k < split.chains.size(); ++k) split.chains[k].group = uint32_t(k % 2);

    auto run = [&](const ChainPlan& plan, ChainRunner::FilmLayout layout) {
        auto runner = mlt.runner(plan, layout);
        ProgressReporter progress(mlt.render.observer, "render", "mutations", 0);
        runner->run(progress, 0);
        return runner;
    };
    auto perGroup = run(mlt.start.plan, ChainRunner::FilmLayout::PerGroup);
    auto withHalves = run(mlt.start.plan, ChainRunner::FilmLayout::PerGroupWithHalves);
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
    const double b = mlt.start.plan.groups[0].b;
    const ErrorSums expected = halvesError(
        asGroups->film(0).resolveCombined(ChainRunner::filmScale(b, st.width, st.height, even)),
        asGroups->film(1).resolveCombined(ChainRunner::filmScale(b, st.width, st.height, odd)),
        double(even), double(odd));
    const ErrorSums got = withHalves->halvesError(0);
    ASSERT_GT(expected.variance, 0.0);
    // Not bit for bit: half A's image is all less the odd half, each resolved to float first.
    EXPECT_NEAR(got.variance, expected.variance, 1e-4 * expected.variance);
    EXPECT_NEAR(got.value, expected.value, 1e-5 * expected.value);
    EXPECT_EQ(got.count, double(st.width) * st.height * 3);
}

TEST(ChainHalves, TakingAGroupsImageGivesBackItsFilmsAndChangesNoBit) {
    MltChains mlt(24, 18, 4, 9, 8);
    auto runner = mlt.runner(mlt.start.plan, ChainRunner::FilmLayout::PerGroupWithHalves);
    ProgressReporter progress(mlt.render.observer, "render", "mutations", 0);
    runner->run(progress, 0);
    const Image expected = runner->resolveGroupCombined(0);
    ASSERT_GT(runner->halvesError(0).count, 0.0);

    const Image taken = runner->takeGroupCombined(0);
    EXPECT_EQ(taken.rgb, expected.rgb);
    // Both of the group's films (its own and its odd half's) are gone, and with them its halves.
    EXPECT_EQ(runner->film(0).width(), 0);
    EXPECT_EQ(runner->film(1).width(), 0);
    EXPECT_EQ(runner->halvesError(0).count, 0.0);
}

TEST(ChainHalves, ARequestedStopEndsTheRunAfterItsRound) {
    MltChains mlt(16, 12, 64, 2, 8);
    auto runner = mlt.runner(mlt.start.plan, ChainRunner::FilmLayout::PerGroup,
                             /*roundMutations=*/16);
    ProgressReporter progress(mlt.render.observer, "render", "mutations", 0);
    int rounds = 0;
    runner->run(progress, 0, [&](double) {
        if (++rounds == 3) runner->requestStop();
    });
    EXPECT_EQ(rounds, 3);
    EXPECT_EQ(runner->mutationsDone(), 3u * 16u * mlt.start.plan.chains.size());
    EXPECT_LT(runner->mutationsDone(), mlt.start.plan.mutations());
}

}  // namespace
}  // namespace partita
