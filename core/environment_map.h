// The environment: radiance arriving from infinitely far away, from an equirectangular
// (latitude-longitude) image or one colour. glTF has no light of its own for it, and most real
// glTF files assume one (DESIGN.md; issue #10).
//
// Convention: a direction d (unit, from the scene towards the sky) maps to
//   u = 1/2 + atan2(d.x, -d.z) / (2 pi),   v = acos(d.y) / pi,
// so +Y (glTF's up) is the top row, and the image centre looks along -Z (glTF's forward); a
// rotation turns the map about +Y (positive: counter-clockwise seen from above).
//
// Radiance is piecewise constant over pixels (no filtering), so that the importance sampling
// below is exact: a pixel is chosen with probability proportional to luminance x sin(theta) of
// its centre (rows first, then the column within the row, each by inverting a CDF), a point
// uniformly within it, and the solid-angle density of direction d is
//   pdf(d) = P(pixel of d) W H / (2 pi^2 sin theta(d)).
#pragma once

#include <vector>

#include "image.h"
#include "math/vec.h"

namespace partita {

class EnvironmentMap {
  public:
    /// `radiance` is the equirectangular image (at least 1x1); `rotationDegrees` about +Y.
    EnvironmentMap(Image radiance, float rotationDegrees = 0);
    /// One colour from every direction (sampled on a 64 x 32 grid: near-uniform on the sphere).
    static EnvironmentMap uniform(Rgb radiance);

    /// Radiance arriving from direction d (unit, pointing away from the scene).
    Rgb radiance(Vec3f d) const;
    /// A direction by importance (u in [0,1)^2) and its solid-angle density; false when the map
    /// is black everywhere.
    bool sample(Vec2f u, Vec3f& d, float& pdf) const;
    /// The solid-angle density with which sample() produces d.
    float pdf(Vec3f d) const;
    /// The radiance averaged over the sphere of directions.
    float meanLuminance() const { return meanLuminance_; }
    bool isBlack() const { return rowCdf_.back() <= 0; }

  private:
    Vec2f uvOf(Vec3f d) const;
    Vec3f directionOf(Vec2f uv) const;
    int pixelIndex(Vec2f uv) const;

    Image image_;
    float cosRot_ = 1, sinRot_ = 0;
    // Piecewise-constant distributions: the rows, then the columns of each row.
    std::vector<float> rowCdf_;     // H + 1 entries, rowCdf_[H] the total weight
    std::vector<float> columnCdf_;  // H x (W + 1): per row, its columns' cumulative weights
    std::vector<float> pixelPmf_;   // W x H
    float meanLuminance_ = 0;
};

}  // namespace partita
