// ImageGuide::candidates (image_guide_candidates.cpp), the guided move's vector loop over Y'(p),
// against sPrime, Eq. 15 written out one candidate at a time: the same weights within float
// rounding, zero at exactly the same candidates, and the same weight for a pixel whichever
// lane computes it (Eq. 16's ratio reads single offsets and needs that exactly).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "camera.h"
#include "gltf/gltf_loader.h"
#include "guide/gbuffer.h"
#include "guide/image_guide.h"
#include "guide/offsets.h"
#include "guide/support_mask.h"
#include "render_scene.h"
#include "renderer.h"
#include "rng.h"
#include "thread_pool.h"

namespace partita {
namespace {

constexpr int kWidth = 48, kHeight = 36;

struct GuideOnCornellGlass {
    RenderScene scene{
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell-glass/cornell-glass.gltf")};
    GBuffer gbuffer;
    SupportMasks masks;

    GuideOnCornellGlass() {
        Camera camera(resolveCamera(scene.data(), ""), kWidth, kHeight);
        RenderSettings settings;
        settings.width = kWidth;
        settings.height = kHeight;
        ThreadPool pool(1);
        std::atomic<bool> cancel{false};
        RenderObserver observer;
        gbuffer = buildGBuffer({scene, camera, settings, pool, cancel, observer});
        // A support that is neither all nor nothing: V' = 1 on a checkerboard, epsilon off it.
        std::vector<float> d(size_t(kWidth * kHeight), 0.0f);
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) d[size_t(y * kWidth + x)] = float((x / 3 + y) % 2);
        masks = SupportMasks({d}, kWidth, kHeight, 0.5f);
    }
};

/// Anchors of every kind Eq. 15 distinguishes: a surface point (with a normal), a point light
/// (no normal: no cos'), one at infinity (neither cos' nor 1 / d^2).
std::vector<PathVertex> anchors(Rng& rng) {
    std::vector<PathVertex> out;
    for (int i = 0; i < 12; ++i) {
        PathVertex v;
        v.p = {2 * rng.nextFloat() - 1, 1.9f * rng.nextFloat(), 2 * rng.nextFloat() - 1};
        if (i % 3 == 0) v.ng = normalize(Vec3f{rng.nextFloat() - 0.5f, -1, rng.nextFloat()});
        if (i % 3 == 2) {
            v.atInfinity = true;
            v.p = v.p * 1e4f;
        }
        out.push_back(v);
    }
    return out;
}

TEST(ImageGuide, CandidatesAreSPrimeOfEachOffsetWithinRounding) {
    GuideOnCornellGlass g;
    ImageGuide guide(g.gbuffer, g.masks, 0);
    Rng rng(3, 1);
    // 33: a partial last lane; 128: the paper's |Y'|. The radius reaches past the image's edges.
    for (int count : {33, 128}) {
        const std::vector<PixelOffset> delta = guideOffsets(count, 20);
        const OffsetLanes lanes(delta);
        size_t compared = 0, zeros = 0;
        for (const PathVertex& anchor : anchors(rng)) {
            for (int trial = 0; trial < 20; ++trial) {
                int px = int(rng.nextFloat() * kWidth), py = int(rng.nextFloat() * kHeight);
                CandidateWeights got;
                guide.candidates(lanes, px, py, anchor, got);
                ASSERT_EQ(got.weights.size(), delta.size());
                double sum = 0;
                for (size_t k = 0; k < delta.size(); ++k) {
                    int x = px + delta[k].dx, y = py + delta[k].dy;
                    bool onImage = x >= 0 && y >= 0 && x < kWidth && y < kHeight;
                    float expected = onImage ? guide.sPrime(x, y, anchor) : 0.0f;
                    sum += double(got.weights[k]);
                    if (expected == 0) {
                        EXPECT_EQ(got.weights[k], 0.0f) << k << " at " << px << "," << py;
                        ++zeros;
                        continue;
                    }
                    // Both sides start from the same d = anchor - position. Each float
                    // operation errs by at most u = eps / 2 relatively, but a dot product of
                    // nearly orthogonal vectors loses relative precision by its condition number
                    // c = sum |n_i d_i| / |n.d| (Higham, Accuracy and Stability, 3.1). First
                    // order, counting roundings:
                    //   sPrime: |d|^2 5 (positive terms), sqrt 1 + 5/2, w = d / |d| 1 more: w's
                    //     components 4.5; each cosine (3 + 4.5) c; / |d|^2 1 + 5; the product
                    //     with the cosines and the four factors 5: 7.5 (c + c') + 11;
                    //   the loop: |d|^2 3 (fmas), each cosine 3 c, |d|^4 2 x 3 + 1, numerator
                    //     1, division 1, the four factors 4: 3 (c + c') + 13;
                    // together at most 10.5 (c + c') + 24 u (the other anchors need fewer).
                    const GBufferTexel& t = g.gbuffer.at(x, y);
                    const Vec3f d = anchor.p - t.position;
                    auto condition = [&](Vec3f n) {
                        double terms = std::abs(double(n.x) * d.x) + std::abs(double(n.y) * d.y) +
                                       std::abs(double(n.z) * d.z);
                        return terms / std::abs(double(dot(n, d)));
                    };
                    const double conditions =
                        condition(t.normal) + (isBlack(anchor.ng) ? 0 : condition(anchor.ng));
                    const double u = std::numeric_limits<float>::epsilon() / 2;
                    EXPECT_NEAR(got.weights[k], expected, (10.5 * conditions + 24) * u * expected)
                        << k << " at " << px << "," << py;
                    ++compared;
                }
                EXPECT_EQ(got.sum, sum);
            }
        }
        EXPECT_GT(compared, 1000u);
        EXPECT_GT(zeros, 100u);  // off the image, invalid texels
    }
}

TEST(ImageGuide, APixelGetsTheSameWeightInEveryLane) {
    GuideOnCornellGlass g;
    ImageGuide guide(g.gbuffer, g.masks, 0);
    // Each of 20 shifts at 20 positions, so that it falls in every lane of the 8-wide loop.
    std::vector<PixelOffset> delta;
    for (int copy = 0; copy < 20; ++copy)
        for (int i = 0; i < 20; ++i) delta.push_back({i % 5 - 2, i / 5 - 2});
    const OffsetLanes lanes(delta);
    Rng rng(5, 1);
    for (const PathVertex& anchor : anchors(rng)) {
        CandidateWeights got;
        guide.candidates(lanes, kWidth / 2, kHeight / 2, anchor, got);
        for (size_t k = 20; k < delta.size(); ++k) EXPECT_EQ(got.weights[k], got.weights[k % 20]);
    }
}

}  // namespace
}  // namespace partita
