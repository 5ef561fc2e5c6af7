// Tests of the figures partita-eval aggregates (tools/eval): spread over seeds, peak memory.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "eval/peak_rss.h"
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

}  // namespace
}  // namespace partita::eval
