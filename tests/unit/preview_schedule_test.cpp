// PreviewSchedule: previews only where asked for and wanted, the first at once, then once per
// interval, spaced by kCostFactor times the last one's cost when that is longer.
#include "preview_schedule.h"

#include <gtest/gtest.h>

#include <chrono>

#include "partitioned_helpers.h"
#include "render_helpers.h"

namespace partita {
namespace {

struct NoPreviews : RenderObserver {
    bool wantsPreviews() const override { return false; }
};

/// An observer whose side takes `delivery` seconds per preview, and wants them while `wanted`.
struct SlowDelivery : RenderObserver {
    double delivery = 2;
    bool wanted = true;
    bool wantsPreviews() const override { return wanted; }
    double previewDeliverySeconds() const override { return delivery; }
};

RenderSettings everySecond() {
    RenderSettings s;
    s.width = 16;
    s.height = 16;
    s.previewIntervalSeconds = 1;
    return s;
}

TEST(PreviewSchedule, OnlyWhereTheSettingsAskAndTheObserverWants) {
    const RenderScene scene = partitioned_test::loadScene("cornell");
    RenderSettings none = everySecond();
    none.previewIntervalSeconds = 0;
    test::TestRenderContext off(scene, none);
    EXPECT_FALSE(PreviewSchedule(off.ctx).enabled());
    EXPECT_FALSE(PreviewSchedule(off.ctx).due());

    test::TestRenderContext on(scene, everySecond());
    EXPECT_TRUE(PreviewSchedule(on.ctx).enabled());
    NoPreviews unwanted;
    RenderContext unwantedCtx{on.ctx.scene, on.ctx.camera, on.ctx.settings,
                              on.ctx.pool,  on.ctx.cancel, unwanted};
    EXPECT_FALSE(PreviewSchedule(unwantedCtx).enabled());
    EXPECT_FALSE(PreviewSchedule(unwantedCtx).due());
}

TEST(PreviewSchedule, TheFirstAtOnceThenOncePerInterval) {
    const RenderScene scene = partitioned_test::loadScene("cornell");
    test::TestRenderContext c(scene, everySecond());
    PreviewSchedule previews(c.ctx);
    EXPECT_TRUE(previews.due());
    EXPECT_EQ(previews.untilDue(), 0.0);
    previews.shown(Clock::now());  // a preview that cost nothing
    EXPECT_DOUBLE_EQ(previews.interval(), 1.0);
    EXPECT_FALSE(previews.due());
    EXPECT_GT(previews.untilDue(), 0.5);
    EXPECT_LE(previews.untilDue(), 1.0);
    // One that began 1.5 s ago and was handed over now (it cost 1.5 s): the next is due 15 s
    // after it began, not 1 s.
    previews.shown(Clock::now() - std::chrono::milliseconds(1500));
    EXPECT_GE(previews.interval(), PreviewSchedule::kCostFactor * 1.5);
    EXPECT_FALSE(previews.due());
    EXPECT_GT(previews.untilDue(), 13.0);
    // A cheap one again: the setting's interval is back.
    previews.shown(Clock::now());
    EXPECT_DOUBLE_EQ(previews.interval(), 1.0);
}

TEST(PreviewSchedule, TheObserversDeliveryCountsAndItsWishIsAskedEachTime) {
    const RenderScene scene = partitioned_test::loadScene("cornell");
    test::TestRenderContext c(scene, everySecond());
    SlowDelivery observer;
    RenderContext ctx{c.ctx.scene, c.ctx.camera, c.ctx.settings,
                      c.ctx.pool,  c.ctx.cancel, observer};
    PreviewSchedule previews(ctx);
    EXPECT_TRUE(previews.due());
    previews.shown(Clock::now());
    // 2 s of encoding on the observer's side: the next preview 20 s after this one began.
    EXPECT_GE(previews.interval(), PreviewSchedule::kCostFactor * 2);
    EXPECT_GT(previews.untilDue(), 19.0);
    observer.delivery = 0;
    EXPECT_DOUBLE_EQ(previews.interval(), 1.0);
    // No one wants previews any more (a daemon job's watchers left): none is due.
    observer.wanted = false;
    EXPECT_FALSE(previews.enabled());
    EXPECT_FALSE(PreviewSchedule(ctx).due());
}

}  // namespace
}  // namespace partita
