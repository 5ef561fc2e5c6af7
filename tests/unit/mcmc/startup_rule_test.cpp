// The start-up rule (mcmc/startup_rule.h, issue #22 3): the bootstrap's samples and the chains'
// burn-in follow the pixels and the budget; what a job asks for explicitly is kept; and the
// renders report what ran (bootstrap_samples / prepass_samples, burn_in).
#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "mcmc/startup_rule.h"
#include "render_helpers.h"

namespace partita {
namespace {

RenderSettings budget(BudgetKind kind, double amount, int width = 64, int height = 48) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    s.budgetKind = kind;
    s.budget = amount;
    s.previewIntervalSeconds = 0;
    return s;
}

RenderScene cornell() {
    return RenderScene(loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf"));
}

TEST(StartupRule, BootstrapSamplesFollowThePixelsAndTheBudget) {
    using R = StartupRule;
    const auto mpp = BudgetKind::MutationsPerPixel;
    // At most the chains' time, a sample costing kSampleCost mutations.
    const RenderSettings mid = budget(mpp, 64, 64, 48);  // 196608 mutations
    EXPECT_EQ(R::bootstrapSamples(0, mid), uint64_t(std::ceil(196608 / R::kSampleCost)));
    EXPECT_GT(R::bootstrapSamples(0, mid), R::kMinSamples);
    EXPECT_LT(R::bootstrapSamples(0, mid), R::kMaxSamples);
    // More pixels or more mutations per pixel: more samples, within the bounds.
    EXPECT_GT(R::bootstrapSamples(0, budget(mpp, 128, 64, 48)), R::bootstrapSamples(0, mid));
    EXPECT_GT(R::bootstrapSamples(0, budget(mpp, 64, 96, 48)), R::bootstrapSamples(0, mid));
    EXPECT_EQ(R::bootstrapSamples(0, budget(mpp, 1, 16, 12)), R::kMinSamples);
    EXPECT_EQ(R::bootstrapSamples(0, budget(mpp, 4096, 1920, 1080)), R::kMaxSamples);
    // A time budget: the most, cut by startup_share of the time while it runs.
    EXPECT_EQ(R::bootstrapSamples(0, budget(BudgetKind::Seconds, 1)), R::kMaxSamples);
    // What a job asks for, whatever the budget.
    EXPECT_EQ(R::bootstrapSamples(20000, mid), 20000u);
    EXPECT_EQ(R::bootstrapSamples(7, budget(BudgetKind::Seconds, 100)), 7u);
}

TEST(StartupRule, BurnInIsAtMostItsShareOfAChainsMutations) {
    const RenderSettings mpp = budget(BudgetKind::MutationsPerPixel, 4);
    EXPECT_EQ(StartupRule::burnIn(1024, 100000, mpp), 1024u);
    EXPECT_EQ(StartupRule::burnIn(1024, 3000, mpp), 300u);
    EXPECT_EQ(StartupRule::burnIn(1024, 5, mpp), 0u);
    // A time budget plans the whole burn-in; the runner stops it at its share of the time.
    EXPECT_EQ(StartupRule::burnIn(1024, 3000, budget(BudgetKind::Seconds, 1)), 1024u);
}

TEST(StartupRule, MltAndPartitionedRunWhatTheRuleGives) {
    RenderScene scene = cornell();
    RenderSettings s = budget(BudgetKind::MutationsPerPixel, 128, 32, 24);  // 98304 mutations
    const double expected = double(StartupRule::bootstrapSamples(0, s));
    ASSERT_GT(expected, double(StartupRule::kMinSamples)) << "a budget inside the bounds";
    RenderResult mlt = test::renderWith(scene, "mlt", s);
    EXPECT_EQ(mlt.stats.values["bootstrap_samples"], expected);
    EXPECT_EQ(mlt.stats.values["burn_in"], 0) << "mlt's chains start from resampled paths";
    EXPECT_GT(mlt.stats.values["bootstrap_rays"], 0);

    // Every partition with chains (estimators=auto sends cornell's per pixel: no burn-in).
    s.parameters.set("estimators", std::string("chains"));
    RenderResult partitioned = test::renderWith(scene, "partitioned", s);
    EXPECT_EQ(partitioned.stats.values["prepass_samples"], expected);
    // 256 chains of ~384 mutations: a burn-in of a tenth of each chain's, not 1024 steps.
    const double perChain =
        partitioned.stats.values["mutations"] / partitioned.stats.values["chains"];
    EXPECT_GT(partitioned.stats.values["burn_in"], 0);
    EXPECT_LE(partitioned.stats.values["burn_in"], std::ceil(perChain * StartupRule::kBurnInShare));
}

TEST(StartupRule, ATimeBudgetsBurnInStopsAtItsShareOfTheTime) {
    // 256 chains x 1024 burn-in steps take ~0.3 s on two threads of this machine (about 2 us a
    // step); a 0.2 s budget leaves them 10% of at most 0.2 s, so they stop well before the end
    // (a faster machine would need a step under 0.1 us to finish them).
    RenderScene scene = cornell();
    RenderSettings s = budget(BudgetKind::Seconds, 0.2, 32, 24);
    s.parameters.set("bootstrap", 4096);
    RenderResult r = test::renderWith(scene, "partitioned", s);
    EXPECT_LT(r.stats.values["burn_in"], 1024);
    EXPECT_GE(r.stats.values["burn_in"], 0);
}

}  // namespace
}  // namespace partita
