// A test-only mutation: an independence proposal that draws a fresh path by a random BDPT
// strategy and knows its exact density. Mixed with a mutation under test, it makes the chain
// ergodic on its own, so any bias the chain shows comes from the mutation's T ratio.
//
// Sampling: the vertex count n uniform in [2, maxDepth + 2], the camera vertex count t uniform
// in [1, n], the subpaths traced to exactly t and n - t vertices (no Russian roulette), then
// connection (s, t). Density of a path y of n vertices:
//   p(y) = 1 / (maxDepth + 1) * 1 / n * sum over the strategies t that can produce y of p_t(y),
// p_t the product of the camera-side densities of y_1 .. y_{t-1} and the light-side ones of
// y_t .. y_{n-1} (recomputeDensities with Dirac coefficients; camera rays uniform over the
// importance support, as in path_edits.h).
#pragma once

#include <climits>

#include "camera.h"
#include "light_emission.h"
#include "mcmc/markov_path.h"
#include "mcmc/mutation.h"
#include "mcmc/path_edits.h"
#include "path/connection.h"
#include "path/path.h"
#include "path/random_walk.h"
#include "render_scene.h"

namespace partita::test {

class IndependentBdptProposal : public Mutation {
  public:
    IndependentBdptProposal(const RenderScene& scene, const Camera& camera, int maxDepth)
        : scene_(scene), camera_(camera), maxDepth_(maxDepth) {}

    std::string name() const override { return "independent"; }
    bool appliesTo(const MarkovPath&) const override { return true; }

    bool propose(const MarkovPath& x, Rng& rng, MarkovPath& y, double& ratio,
                 uint64_t& rays) override {
        if (!sample(rng, y, rays)) return false;
        double forward = density(y.vertices);
        if (!(forward > 0)) return false;
        ratio = density(x.vertices) / forward;
        return true;
    }

    /// A fresh path (false when the strategy produced nothing).
    bool sample(Rng& rng, MarkovPath& y, uint64_t& rays) const {
        int n = 2 + int(rng.nextBounded(uint32_t(maxDepth_ + 1)));
        int t = 1 + int(rng.nextBounded(uint32_t(n)));
        int s = n - t;
        WalkSettings walk;
        walk.rouletteStartDepth = INT_MAX;
        walk.maxVertices = t;
        Vec2f raster = sampleSupportRaster(camera_, {rng.nextFloat(), rng.nextFloat()});
        std::vector<PathVertex> eye, light;
        traceCameraSubpath(scene_, camera_, camera_.generateRay(raster), rng, walk, eye, rays);
        if (int(eye.size()) != t) return false;
        if (s == 1 && t >= 2) {
            light.resize(1);  // next-event estimation samples its own light vertex
        } else if (s >= 1) {
            walk.maxVertices = s;
            traceLightSubpath(scene_, rng, walk, light, rays);
            if (int(light.size()) != s) return false;
        }
        Connector connector(scene_, camera_, /*keepPaths=*/true);
        StrategySample c = connector.connect(eye, light, s, t, rng, rays, /*weighted=*/false);
        if (!c.valid) return false;
        y.vertices = connector.lastPath();
        return evaluatePath(scene_, camera_, y);
    }

    double density(const std::vector<PathVertex>& p) const {
        int n = int(p.size());
        if (n < 2 || n - 2 > maxDepth_) return 0;
        std::vector<VertexDensities> d =
            recomputeDensities(scene_, camera_, p, DiracVertices::Coefficient);
        double sum = 0;
        for (int t = 1; t <= n; ++t) {
            if (!canSample(p, t)) continue;
            double pt = 1;
            for (int i = 1; i < t; ++i)
                pt *= d[size_t(i)].fromEye * (i == 1 ? cameraSupportScale(camera_) : 1.0f);
            for (int i = t; i < n; ++i) pt *= d[size_t(i)].fromLight;
            sum += pt;
        }
        return sum / (double(n) * double(maxDepth_ + 1));
    }

    double strategyDensity(const std::vector<PathVertex>& p, int t) const {
        int n = int(p.size());
        std::vector<VertexDensities> d =
            recomputeDensities(scene_, camera_, p, DiracVertices::Coefficient);
        double pt = 1;
        for (int i = 1; i < t; ++i)
            pt *= d[size_t(i)].fromEye * (i == 1 ? cameraSupportScale(camera_) : 1.0f);
        for (int i = t; i < n; ++i) pt *= d[size_t(i)].fromLight;
        return pt;
    }

  private:
    bool canSample(const std::vector<PathVertex>& p, int t) const {
        int n = int(p.size());
        const PathVertex& last = p.back();
        if (t == n) return isHittableLight(scene_.lights()[size_t(last.light)]);
        return connectable(camera_, p[size_t(t - 1)], p[size_t(t)], t == n - 1);
    }

    const RenderScene& scene_;
    const Camera& camera_;
    int maxDepth_;
};

}  // namespace partita::test
