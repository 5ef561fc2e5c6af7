// When a progressive render shows its next preview (RenderObserver::onPreview): the first as
// soon as there is an image, then once per preview interval, but never more often than
// kCostFactor times what the last preview cost: the render's resolve of every layer (on the
// pool, while no sample is taken) and the observer's delivery (RenderObserver::
// previewDeliverySeconds: the daemon encodes every layer as a PNG for its watchers, on a
// thread that competes with the render's). So previews take at most about 1 / kCostFactor of
// the render's time each way, whatever the image size and its number of layers: at 1280x720
// with 33 type layers a preview a second made a watched path-traced job 1.6x slower. Whether
// previews are wanted is asked each time (a daemon job makes them while someone watches).
#pragma once

#include "algorithm.h"
#include "cost_bounded_schedule.h"

namespace partita {

class PreviewSchedule {
  public:
    static constexpr double kCostFactor = 10;

    /// Previews only where the settings ask for them (an interval > 0) and the observer wants
    /// them.
    explicit PreviewSchedule(const RenderContext& ctx)
        : observer_(ctx.observer),
          enabledBySettings_(ctx.settings.previewIntervalSeconds > 0),
          schedule_(ctx.settings.previewIntervalSeconds, kCostFactor) {}

    bool enabled() const { return enabledBySettings_ && observer_.wantsPreviews(); }
    /// The seconds between two previews now: the setting's, or kCostFactor times the last
    /// preview's cost (the render's and the observer's) if that is longer.
    double interval() const { return schedule_.interval(observer_.previewDeliverySeconds()); }
    /// Whether a preview is due: the first one, or interval() after the last one began.
    bool due() const { return enabled() && schedule_.due(observer_.previewDeliverySeconds()); }
    /// Seconds until the next preview is due (0 when due), to size the work before it.
    double untilDue() const { return schedule_.untilDue(observer_.previewDeliverySeconds()); }
    /// A preview that began at `began` has been handed over now.
    void shown(Clock::time_point began) { schedule_.ran(began); }

  private:
    const RenderObserver& observer_;
    bool enabledBySettings_;
    CostBoundedSchedule schedule_;
};

}  // namespace partita
