// The chains' target damps paths with very short edges (issue #22 2: chains that never stick).
//
// A chain's target is f*(x) = lum(f(x)) tau(x), with
//     tau(x) = prod over the path's edges e of min(1, |e|^2 / eps^2),
// eps = kShortEdgeShare of the scene's bounding-box diagonal (RenderScene::shortEdge). The
// MLT estimator is unbiased for any target that is positive wherever f is (Veach 1997, Sec.
// 11.3: each splat is f / f* times b* / N with b* = integral of f*, here estimated by the
// bootstrap with the same tau), so tau changes only where the chains spend their time, not
// what the image converges to.
//
// Why: where two surfaces meet (pool's water surface and its walls, at the waterline) a path can
// bounce between them over edges of 0.05-0.5 mm. Its f grows as 1 / |e|^2 per edge, faster than
// any strategy's density: the MIS-combined f / p of such paths was 4e3-1.5e4 against ~1 for a
// typical path, every strategy's firefly. A chain that entered one stayed for the rest of the
// run (no proposal, the independence one included, was accepted in 60-95 thousand mutations),
// and its splats made a blob of 10-17 in a pixel whose reference is 0.1: at 40 s these stuck
// chains held most of pool's squared error and its error stopped falling with the budget
// (docs/mlt-equal-time.md). With tau such paths weigh as little in the target as their
// neighbours do; their light is carried by larger splats of the chains that pass there.
#pragma once

#include <algorithm>

#include "math/vec.h"

namespace partita {

/// eps as a share of the scene's bounding-box diagonal: 1 mm in a 1-m box.
inline constexpr float kShortEdgeShare = 1e-3f;

/// Accumulates tau over the vertices of a path given in order.
class ShortEdgeDamping {
  public:
    explicit ShortEdgeDamping(float shortEdge) : epsSquared_(shortEdge * shortEdge) {}
    void add(Vec3f p) {
        if (hasPrevious_) {
            const Vec3f d = p - previous_;
            const float lengthSquared = dot(d, d);
            if (lengthSquared < epsSquared_) factor_ *= lengthSquared / epsSquared_;
        }
        previous_ = p;
        hasPrevious_ = true;
    }
    float factor() const { return factor_; }

  private:
    float epsSquared_;
    Vec3f previous_;
    bool hasPrevious_ = false;
    float factor_ = 1;
};

}  // namespace partita
