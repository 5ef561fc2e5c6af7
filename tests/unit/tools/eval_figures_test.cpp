// Tests of the figures partita-eval aggregates (tools/eval): spread over seeds, peak memory,
// figures from the renders' statistics.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "eval/peak_rss.h"
#include "eval/run_figures.h"
#include "eval/spread.h"

namespace partita::eval {
namespace {

TEST(Spread, IsTheMeanAndTheSampleStandardDeviation) {
    Spread s = spreadOf({1.0, 2.0, 3.0, 4.0});
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_DOUBLE_EQ(s.std, std::sqrt(5.0 / 3.0));  // squares 2.25+0.25+0.25+2.25 over n - 1
    EXPECT_DOUBLE_EQ(spreadOf({7.0}).mean, 7.0);
    EXPECT_DOUBLE_EQ(spreadOf({7.0}).std, 0.0);
    EXPECT_DOUBLE_EQ(spreadOf({}).mean, 0.0);
}

TEST(PeakRss, ResetsToTheCurrentAndGrowsWithTouchedMemory) {
    if (!resetPeakRss()) GTEST_SKIP() << "this kernel refuses to reset VmHWM";
    double before = peakRssMb();
    EXPECT_GT(before, 0);
    EXPECT_LE(before, currentRssMb() + 1);  // just reset: the peak is what is resident
    constexpr size_t kBytes = size_t(64) << 20;
    auto block = std::make_unique<char[]>(kBytes);
    std::memset(block.get(), 1, kBytes);  // touched, so resident
    EXPECT_GE(peakRssMb(), before + 60);
    block.reset();
    ASSERT_TRUE(resetPeakRss());
    EXPECT_LT(peakRssMb(), before + 32);  // the freed block no longer counts
}

TEST(RunFigures, MeanStatisticsCountOnlyTheSeedsThatReportedThem) {
    Statistics m = meanStatistics({{{"a", 1}, {"b", 10}}, {{"a", 3}}});
    EXPECT_DOUBLE_EQ(m.at("a"), 2.0);
    EXPECT_DOUBLE_EQ(m.at("b"), 10.0);  // one seed reported it
    EXPECT_TRUE(meanStatistics({}).empty());
}

TEST(RunFigures, SecondsPerUnitIsSamplingTimeOverUnitsDone) {
    // 2 s of chains for 4 mutations per pixel on 100 pixels: 5 ms per mutation.
    EXPECT_DOUBLE_EQ(*secondsPerUnit({{"render_seconds", 2.0}}, 4.0, 100.0), 0.005);
    EXPECT_FALSE(secondsPerUnit({{"seconds", 2.0}}, 4.0, 100.0));         // no sampling time
    EXPECT_FALSE(secondsPerUnit({{"render_seconds", 2.0}}, 0.0, 100.0));  // nothing done
}

TEST(RunFigures, AcceptancePerMutationSkipsSeedsThatDidNotProposeIt) {
    std::vector<Statistics> seeds = {{{"acceptance_lens", 0.5},
                                      {"proposed_lens", 10},
                                      {"acceptance_caustic", 0},
                                      {"proposed_caustic", 0}},
                                     {{"acceptance_lens", 0.25},
                                      {"proposed_lens", 30},
                                      {"acceptance_caustic", 0.9},
                                      {"proposed_caustic", 5}},
                                     {{"spp", 4}}};  // no mutations at all
    auto a = acceptancePerMutation(seeds);
    ASSERT_EQ(a.size(), 2u);
    EXPECT_DOUBLE_EQ(*a.at("lens"), 0.375);   // mean over seeds, not weighted by proposals
    EXPECT_DOUBLE_EQ(*a.at("caustic"), 0.9);  // the first seed proposed none
    EXPECT_FALSE(acceptancePerMutation({{{"acceptance_x", 0}, {"proposed_x", 0}}}).at("x"));
    EXPECT_TRUE(acceptancePerMutation({{{"spp", 4}}}).empty());
}

TEST(RunFigures, OverallAcceptanceWeighsTypesByProposals) {
    Statistics s = {{"acceptance_lens", 0.5},
                    {"proposed_lens", 10},
                    {"acceptance_caustic", 0.1},
                    {"proposed_caustic", 30}};
    EXPECT_DOUBLE_EQ(*overallAcceptance(s), (5.0 + 3.0) / 40.0);
    EXPECT_DOUBLE_EQ(*overallAcceptance({{"acceptance", 0.7}, {"acceptance_lens", 0.1}}), 0.7);
    EXPECT_FALSE(overallAcceptance({{"spp", 16}}));
    EXPECT_FALSE(overallAcceptance({{"acceptance_lens", 0}, {"proposed_lens", 0}}));
}

}  // namespace
}  // namespace partita::eval
