// `partitioned` (paper Sec. 4): the partitions cover path space exactly once, b_i agrees with an
// independent estimate of the integral of f* over partition i, each partition's image and the
// combined image converge to the BDPT reference (summed over each partition's types), the
// edge cases (K = 0, fewer types than K, a black image) are defined, and a cancel stops it in
// the pre-pass and in the chains. Tolerances come from the spread over independent seeds.
#include <gtest/gtest.h>

#include <chrono>

#include "camera.h"
#include "film.h"
#include "gltf/gltf_loader.h"
#include "integrators/partitioned/partitioned_integrator.h"
#include "mcmc/chain_runner.h"
#include "mcmc/independence_mutation.h"
#include "mcmc/veach_mutations.h"
#include "params/job_parameters.h"
#include "partition/partition.h"
#include "partition/partition_chains.h"
#include "partition/partitioned_pipeline.h"
#include "partition/prepass.h"
#include "partitioned_helpers.h"
#include "progress_reporter.h"
#include "render_helpers.h"
#include "renderer.h"
#include "scene_builders.h"
#include "thread_pool.h"

namespace partita {
namespace {

using namespace partitioned_test;

TEST(Partitioned, PartitionsCoverPathSpaceExactlyOnce) {
    RenderScene scene = loadScene("cornell-glass");
    LayeredImage bdpt =
        test::renderWith(scene, "bdpt", tinySettings(64, 1, BudgetKind::SamplesPerPixel)).image;
    for (auto [shape, directApart] :
         {std::pair{PartitionShape::Types, false}, std::pair{PartitionShape::Classes, false},
          std::pair{PartitionShape::Types, true}, std::pair{PartitionShape::Classes, true}}) {
        SCOPED_TRACE(testing::Message() << (shape == PartitionShape::Types ? "types" : "classes")
                                        << (directApart ? ", direct light apart" : ""));
        std::vector<Partition> partitions = partitionsOf(scene, 10, 3, 20000, shape, directApart);
        ASSERT_EQ(partitions.size(), directApart ? 12u : 11u);
        EXPECT_TRUE(partitions.back().complement);
        // The direct light apart: first, per pixel, exactly its class; no other holds any of it.
        EXPECT_EQ(partitions.front().direct, directApart);
        if (directApart) {
            EXPECT_EQ(partitions.front().label, kDirectLabel);
            EXPECT_TRUE(partitions.front().perPixel);
            size_t direct = 0;
            for (const ImageLayer& layer : bdpt.layers) {
                PathType t;
                ASSERT_TRUE(PathType::parse(layer.name, t)) << layer.name;
                EXPECT_EQ(partitions.front().holds(t), isDirectLightType(t)) << layer.name;
                direct += isDirectLightType(t);
            }
            EXPECT_GT(direct, 0u);  // both kinds occur: the check above can fail either way
            EXPECT_LT(direct, bdpt.layers.size());
        }
        // Every type of the reference lies in exactly one partition ...
        for (const ImageLayer& layer : bdpt.layers) {
            PathType t;
            ASSERT_TRUE(PathType::parse(layer.name, t)) << layer.name;
            int holders = 0;
            for (const Partition& p : partitions) holders += p.holds(t);
            EXPECT_EQ(holders, 1) << layer.name;
        }
        // ... so the partitions' references add up to the full reference, pixel by pixel.
        Image sum(kWidth, kHeight);
        for (const Partition& p : partitions) {
            Image ref = partitionReference(bdpt, p);
            for (size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += ref.rgb[i];
        }
        for (size_t i = 0; i < sum.rgb.size(); ++i)
            EXPECT_NEAR(sum.rgb[i], bdpt.combined.rgb[i], 1e-5 * (1 + bdpt.combined.rgb[i])) << i;
        double totalP = 0;
        for (const Partition& p : partitions) totalP += p.p;
        EXPECT_NEAR(totalP, 1.0, 1e-12);
    }
    // Classes leave the complement less of b than the same number of exact types (issue #23 2).
    EXPECT_LT(complementShareOfB(partitionsOf(scene, 10, 3, 20000, PartitionShape::Classes)),
              complementShareOfB(partitionsOf(scene, 10, 3, 20000, PartitionShape::Types)));
}

/// What the chains of each partition splatted, with or without the partitions' restriction:
/// the layers (types) with energy outside their partition, and the classes whose chains
/// splatted more than one type.
struct SplatCount {
    int outside = 0, classesOfSeveralTypes = 0;
};

SplatCount countClassSplats(bool restricted) {
    RenderScene scene = loadScene("cornell-glass");
    Camera camera(resolveCamera(scene.data(), ""), kWidth, kHeight);
    RenderSettings st = tinySettings(4, 5, BudgetKind::MutationsPerPixel);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    BootstrapSampler sampler(scene, camera, kMaxDepth, 5, StartupEstimator::Bidirectional);
    const PrepassResult pre = runPrepass(ctx, sampler, 20000);
    const std::vector<Partition> partitions =
        makePartitions(pre, 4, kMaxBRelativeError, PartitionShape::Classes);
    ChainPlan plan = planPartitionChains(
        ctx, sampler, pre, partitions,
        allocateMutations(partitions, uint64_t(4 * kWidth * kHeight)), PartitionPipelineSettings{});
    plan.layers = TypeLayers::every();  // the render's films keep none: here, every type
    ChainRunner runner(
        ctx, plan,
        [&](uint32_t g) {
            return makeVeachMutations(scene, camera, kMaxDepth,
                                      partitionMutationSettings({}, partitions[g]));
        },
        [&](uint32_t g) -> PathRestriction {
            if (!restricted) return {};
            const Partition p = partitions[g];
            return [p](const PathType& t) { return p.holds(t); };
        });
    ProgressReporter progress(observer, "render", "mutations", double(plan.mutations()));
    runner.run(progress, 0);
    SplatCount count;
    for (uint32_t g = 0; g < partitions.size(); ++g) {
        int typesSplatted = 0;
        for (const ImageLayer& layer : runner.resolveGroup(g, &pool).layers) {
            double energy = 0;
            for (float v : layer.image.rgb) energy += v;
            EXPECT_NE(layer.name, Film::kOtherLayer) << "every type has a layer here";
            PathType t;
            if (energy == 0 || !PathType::parse(layer.name, t)) continue;
            count.outside += !partitions[g].holds(t);
            ++typesSplatted;
        }
        const bool isClass = !partitions[g].complement && !partitions[g].patterns[0].isExact();
        count.classesOfSeveralTypes += isClass && typesSplatted > 1;
    }
    return count;
}

/// Classes (issue #23 2): chains restricted to a class splat only paths of its types (a count
/// over the per-type layers of each partition's film), and a class's chains reach more than one
/// of its types; without the restriction the same chains leave their classes (the count can
/// fail).
TEST(Partitioned, ClassChainsSplatOnlyTheirClass) {
    const SplatCount restricted = countClassSplats(true);
    EXPECT_EQ(restricted.outside, 0);
    EXPECT_GT(restricted.classesOfSeveralTypes, 0);
    EXPECT_GT(countClassSplats(false).outside, 0);
}

/// b_i over independent pre-passes against importance sampling with the exact density of
/// mcmc/independence_mutation.h, per partition (the partitions fixed by one pre-pass).
TEST(Partitioned, BiAgreesWithAnIndependentEstimatePerPartition) {
    RenderScene scene = loadScene("cornell-glass");
    Camera camera(resolveCamera(scene.data(), ""), kWidth, kHeight);
    std::vector<Partition> fixed = partitionsOf(scene, 5, 3, 20000);
    const int seeds = 8;
    std::vector<std::vector<double>> prepassB(fixed.size()), importance(fixed.size());
    IndependenceMutation independent(scene, camera, kMaxDepth);
    for (int seed = 0; seed < seeds; ++seed) {
        // b_i of the fixed partitions from a fresh pre-pass: half B's sums over their types.
        RenderSettings st = tinySettings(1, 40 + uint64_t(seed), BudgetKind::MutationsPerPixel);
        ThreadPool pool(2);
        std::atomic<bool> cancel{false};
        RenderObserver observer;
        RenderContext ctx{scene, camera, st, pool, cancel, observer};
        BootstrapSampler sampler(scene, camera, kMaxDepth, 40 + uint64_t(seed),
                                 StartupEstimator::PathTracer);
        PrepassResult pre = runPrepass(ctx, sampler, 40000);
        std::vector<double> isSums(fixed.size(), 0.0);
        Rng rng(80 + uint64_t(seed), 0);
        uint64_t rays = 0;
        const int isSamples = 40000;
        for (int i = 0; i < isSamples; ++i) {
            MarkovPath y;
            if (!independent.sample(rng, y, rays)) continue;
            for (size_t g = 0; g < fixed.size(); ++g)
                if (fixed[g].holds(y.type)) isSums[g] += y.fStar / independent.density(y.vertices);
        }
        for (size_t g = 0; g < fixed.size(); ++g) {
            double sum = 0;
            for (const auto& [type, c] : pre.sumB)
                if (fixed[g].holds(type)) sum += c;
            prepassB[g].push_back(sum / double(pre.samplesB));
            importance[g].push_back(isSums[g] / isSamples);
        }
    }
    for (size_t g = 0; g < fixed.size(); ++g) {
        auto a = test::meanAndError(prepassB[g]), b = test::meanAndError(importance[g]);
        EXPECT_GT(a.mean, 0) << fixed[g].label;
        EXPECT_NEAR(a.mean, b.mean, test::twoSampleTolerance(a, b, int(fixed.size())))
            << fixed[g].label << ": pre-pass " << a.mean << " +- " << a.standardError
            << ", importance sampling " << b.mean << " +- " << b.standardError;
    }
}

/// `auto` (issue #23 1): each partition by the estimator its pilots choose; the mixture of
/// chain and per-pixel partitions converges partition by partition and combined.
TEST(Partitioned, PartitionsConvergeOnCornellGlass) {
    // The direct light with the types: on cornell-glass auto then mixes chains and per-pixel
    // partitions (with it apart, everything goes per pixel there).
    const EstimatorCounts counts = expectPartitionsConverge(
        "partitioned", "cornell-glass", 64, 64, 10, {{"estimators", "auto"}, {"direct", "chains"}});
    EXPECT_GT(counts.chains, 0);
    EXPECT_GT(counts.perPixel, 0);
}

/// auto's default: the direct light a partition of its own, per pixel, the other partitions
/// holding none of it; a mixture of chains and per-pixel partitions on door-ajar.
TEST(Partitioned, PartitionsWithTheDirectLightApartConvergeOnDoorAjar) {
    const EstimatorCounts counts =
        expectPartitionsConverge("partitioned", "door-ajar", 64, 64, 10, {{"estimators", "auto"}});
    EXPECT_GT(counts.chains, 0);
    EXPECT_GT(counts.perPixel, 0);
    EXPECT_EQ(counts.direct, 10);  // every seed's render has it
}

/// The paper's method exactly: chains for every partition, mutations by Eq. 10.
TEST(Partitioned, PartitionsConvergeOnDoorAjar) {
    const EstimatorCounts counts = expectPartitionsConverge(
        "partitioned", "door-ajar", 64, 64, 10, {{"estimators", "chains"}, {"allocation", "p"}});
    EXPECT_EQ(counts.perPixel, 0);
}

/// Classes of types (issue #23 2) with chains: each class's image converges to bdpt's layers of
/// the types it holds.
TEST(Partitioned, ClassPartitionsConvergeOnCornellGlass) {
    const EstimatorCounts counts =
        expectPartitionsConverge("partitioned", "cornell-glass", 64, 64, 10,
                                 {{"estimators", "chains"}, {"partitions", "classes"}});
    EXPECT_EQ(counts.perPixel, 0);
}

/// Every partition per pixel (BDPT restricted to its types) converges to bdpt's layers of them.
TEST(Partitioned, PerPixelPartitionsConvergeOnCornellGlass) {
    const EstimatorCounts counts = expectPartitionsConverge("partitioned", "cornell-glass", 64, 16,
                                                            10, {{"estimators", "per-pixel"}});
    EXPECT_EQ(counts.chains, 0);
}

TEST(Partitioned, EdgeCasesAreDefined) {
    RenderScene scene = loadScene("cornell");
    RenderSettings st = tinySettings(8, 1, BudgetKind::MutationsPerPixel);
    // K = 0: the complement alone, all of path space (the paper's partitions: with the estimators
    // chosen, the direct light would be a partition too).
    st.parameters.set("k", 0).set("estimators", std::string("chains"));
    RenderResult none = test::renderWith(scene, "partitioned", st);
    ASSERT_EQ(none.image.layers.size(), 1u);
    EXPECT_EQ(none.image.layers[0].name, kComplementLabel);
    EXPECT_EQ(none.image.layers[0].image.rgb, none.image.combined.rgb);
    // More partitions asked for than types exist: every type is a partition, no complement.
    SceneData furnace = test::furnaceScene(0.5f, 1.0f);
    RenderScene small(std::move(furnace));
    st.parameters.set("k", 64);
    st.maxDepth = 2;
    RenderResult all = test::renderWith(small, "partitioned", st);
    ASSERT_EQ(all.image.layers.size(), 3u);  // LE, LDE, LDDE
    for (const auto& layer : all.image.layers) EXPECT_NE(layer.name, kComplementLabel);
    // A black scene: no partition, a black image.
    SceneData dark = test::specularBoxScene();
    dark.materials[1].emissiveFactor = Rgb(0.0f);
    RenderScene black(std::move(dark));
    st.parameters.set("k", 10);
    RenderResult r = test::renderWith(black, "partitioned", st);
    EXPECT_TRUE(r.image.layers.empty());
    EXPECT_EQ(luminance(r.image.combined.mean()), 0.0f);
    EXPECT_EQ(r.stats.values["mutations"], 0.0);
}

TEST(Partitioned, PrepassEstimatorFollowsTheSetting) {
    std::string why;
    RenderScene area = loadScene("cornell-glass");
    EXPECT_EQ(choosePrepassEstimator(area, "auto", why), StartupEstimator::PathTracer);
    RenderScene point = loadScene("cornell-point");
    EXPECT_EQ(choosePrepassEstimator(point, "auto", why), StartupEstimator::Bidirectional);
    EXPECT_NE(why.find("delta light"), std::string::npos);
    EXPECT_EQ(choosePrepassEstimator(point, "pt", why), StartupEstimator::PathTracer);
    EXPECT_THROW(choosePrepassEstimator(point, "magic", why), std::invalid_argument);
    RenderSettings st = tinySettings(4, 1, BudgetKind::MutationsPerPixel);
    st.parameters.set("prepass", "magic");
    EXPECT_EQ(validateJob(registeredAlgorithm("partitioned"), st),
              "prepass 'magic' is not one of auto | pt | bdpt");
}

/// Raises the cancel flag once `phase` has run for 0.2 s; records when.
class CancelInPhase : public RenderObserver {
  public:
    CancelInPhase(std::atomic<bool>& cancel, std::string phase)
        : cancel_(cancel), phase_(std::move(phase)) {}
    void onProgress(const RenderProgress& p) override {
        if (p.phase != phase_ || cancel_) return;
        auto now = std::chrono::steady_clock::now();
        if (!started_) {
            started_ = true;
            start_ = now;
        }
        if (std::chrono::duration<double>(now - start_).count() >= 0.2) {
            at_ = now;
            cancel_ = true;
        }
    }
    std::atomic<bool>& cancel_;
    std::string phase_;
    bool started_ = false;
    std::chrono::steady_clock::time_point start_, at_;
};

double secondsToCancel(PartitionedSettings settings, const std::string& phase) {
    RenderScene scene = loadScene("cornell-glass");
    RenderSettings st = tinySettings(1e6, 1, BudgetKind::MutationsPerPixel);
    st.width = 64;
    st.height = 48;
    Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    CancelInPhase observer(cancel, phase);
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    PartitionedAlgorithm algorithm(settings);
    EXPECT_THROW(algorithm.render(ctx), RenderCancelled);
    EXPECT_TRUE(cancel.load()) << "the phase " << phase << " never ran long enough";
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - observer.at_).count();
}

TEST(Partitioned, ATimeBudgetsPrepassStopsAtItsShare) {
    // A 1-second job asking for 2^30 pre-pass samples was still in its pre-pass after 6 s
    // (issue #25 2); now the pre-pass stops after startup_share of the budget, its halves
    // counting the samples that ran, and the chains get the rest.
    RenderSettings st = tinySettings(1, 1, BudgetKind::Seconds);
    st.budget = 1;
    st.parameters.set("bootstrap", uint64_t(1) << 30).set("k", 3);
    RenderResult r = test::renderWith(loadScene("cornell"), "partitioned", st);
    EXPECT_EQ(r.stats.values["prepass_samples_requested"], double(uint64_t(1) << 30));
    EXPECT_GT(r.stats.values["prepass_samples"], 0.0);
    EXPECT_LT(r.stats.values["prepass_samples"], double(uint64_t(1) << 24));
    // The rest goes to the chains or, for partitions a per-pixel estimator does better, to
    // per-pixel samples (issue #23 1).
    EXPECT_GT(r.stats.values["mutations"] + r.stats.values["per_pixel_spp"], 0.0)
        << "the render got the rest";
}

TEST(Partitioned, CancelStopsWithinASecondInThePrepass) {
    PartitionedSettings s;
    s.bootstrapSamples = 100000000;
    EXPECT_LT(secondsToCancel(s, "prepass"), 1.0);
}

TEST(Partitioned, CancelStopsWithinASecondInTheChains) {
    PartitionedSettings s;
    s.bootstrapSamples = 4000;
    EXPECT_LT(secondsToCancel(s, "render"), 1.0);
}

}  // namespace
}  // namespace partita
