#include "service_limits.h"

namespace partita::server {

RenderLimits ServiceLimits::renderLimits() const {
    RenderLimits r;
    r.maxWidth = maxWidth;
    r.maxHeight = maxHeight;
    r.maxSamplesPerPixel = maxSamplesPerPixel;
    r.maxSeconds = maxSeconds;
    r.maxDepth = maxDepth;
    r.maxBootstrapSamples = maxBootstrapSamples;
    return r;
}

}  // namespace partita::server
