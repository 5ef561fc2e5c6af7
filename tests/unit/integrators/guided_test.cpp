// `guided` (paper Sec. 5 on Sec. 4's partitions): each partition's image and the combined image
// converge to the BDPT reference on cornell-glass, door-ajar and pool (the same check as
// `partitioned`'s, partitioned_helpers.h, tolerances from the spread over independent seeds);
// the guided perturbation does the lens perturbation's work (it is proposed and accepted); the
// guides are reported; bad guide parameters are clear errors. The same image for 1 and 2
// threads is EveryAlgorithm's (integrators/every_algorithm_test.cpp), which covers every registered
// algorithm.
#include <gtest/gtest.h>

#include "params/job_parameters.h"
#include "partitioned_helpers.h"
#include "render_helpers.h"
#include "renderer.h"

namespace partita {
namespace {

using namespace partitioned_test;

TEST(Guided, PartitionsConvergeOnCornellGlass) {
    expectPartitionsConverge("guided", "cornell-glass", 64, 64, 10, {{"estimators", "chains"}});
}

TEST(Guided, PartitionsConvergeOnDoorAjar) {
    expectPartitionsConverge("guided", "door-ajar", 64, 64, 10, {{"estimators", "chains"}});
}

TEST(Guided, PartitionsConvergeOnPool) {
    expectPartitionsConverge("guided", "pool", 64, 64, 10, {{"estimators", "chains"}});
}

TEST(Guided, TheGuidedPerturbationReplacesTheLensPerturbation) {
    RenderScene scene = loadScene("cornell-glass");
    RenderSettings st = tinySettings(32, 3, BudgetKind::MutationsPerPixel);
    // Every partition with chains (estimators=auto may give cornell-glass's to per-pixel samples).
    st.parameters.set("y", 33).set("radius", 4).set("estimators", std::string("chains"));
    RenderResult r = test::renderWith(scene, "guided", st);
    EXPECT_GT(r.stats.values["proposed_guided"], 1000);
    EXPECT_GT(r.stats.values["acceptance_guided"], 0.05);
    EXPECT_EQ(r.stats.values.count("proposed_lens"), 0u);
    EXPECT_EQ(r.stats.values["guide_candidates"], 33);
    EXPECT_EQ(r.stats.values["guide_radius"], 4);
    EXPECT_GT(r.stats.values["guide_bytes"], 0);
    // Every partition's V' holds some pixels, not all (the complement's may hold everything).
    double partitions = r.stats.values["partitions"];
    ASSERT_GE(partitions, 2);
    for (int g = 0; g + 1 < int(partitions); ++g) {
        double support = r.stats.values["partition_" + std::to_string(g) + "_guide_support"];
        EXPECT_GT(support, 0) << g;
    }
}

TEST(Guided, BadGuideParametersAreClearErrors) {
    RenderSettings st = tinySettings(4, 1, BudgetKind::MutationsPerPixel);
    const AlgorithmRegistry::Entry& guided = registeredAlgorithm("guided");
    st.parameters.set("y", 0);
    EXPECT_EQ(validateJob(guided, st), "y = 0 is outside [1, 4096] pixels");
    st.parameters.set("y", 128).set("radius", -1);
    EXPECT_EQ(validateJob(guided, st), "radius = -1 is outside (0, 4096] pixels");
    st.parameters.set("radius", "wide");
    EXPECT_EQ(validateJob(guided, st), "radius must be a number, got 'wide'");
}

}  // namespace
}  // namespace partita
