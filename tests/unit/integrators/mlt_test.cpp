// `mlt` as a whole (integrators/mlt, mcmc/bootstrap, mcmc/chain_plan): the image converges to
// the BDPT reference combined and per path type; b agrees with an independent estimate of the
// integral of f*; a black scene is a black image; the chain plan survives serialisation and
// refuses garbage; a cancel stops it within a second in both phases. Tolerances come from the
// spread over independent seeds on both sides.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "camera.h"
#include "film.h"
#include "gltf/gltf_loader.h"
#include "integrators/mlt/mlt_integrator.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_plan.h"
#include "mcmc/independence_mutation.h"
#include "params/job_parameters.h"
#include "render_helpers.h"
#include "renderer.h"
#include "scene_builders.h"
#include "thread_pool.h"

namespace partita {
namespace {

constexpr int kWidth = 16, kHeight = 12, kBlocksX = 4, kBlocksY = 3;

RenderScene loadScene(const std::string& name) {
    return RenderScene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/" + name + "/" + name + ".gltf"));
}

RenderSettings tinySettings(double budget, uint64_t seed) {
    RenderSettings st;
    st.width = kWidth;
    st.height = kHeight;
    st.budget = budget;
    st.seed = seed;
    st.maxDepth = 8;
    st.previewIntervalSeconds = 0;
    return st;
}

/// Per block of the image, the mean luminance of the combined image and of each listed layer.
std::vector<double> blockMeans(const LayeredImage& image, const std::vector<std::string>& types) {
    std::vector<double> out;
    auto addBlocks = [&](const Image* img) {
        std::vector<double> blocks(kBlocksX * kBlocksY, 0.0);
        for (int y = 0; y < kHeight && img; ++y)
            for (int x = 0; x < kWidth; ++x)
                blocks[size_t((y * kBlocksY / kHeight) * kBlocksX + x * kBlocksX / kWidth)] +=
                    luminance(img->at(x, y));
        out.insert(out.end(), blocks.begin(), blocks.end());
    };
    addBlocks(&image.combined);
    for (const std::string& t : types) addBlocks(image.layer(t));
    return out;
}

/// mlt at `mpp` against BDPT at `spp`, `seeds` independent seeds each, per block combined and
/// for the brightest types.
void expectMltMatchesBdpt(const std::string& sceneName, double mpp, double spp, int seeds) {
    RenderScene scene = loadScene(sceneName);
    LayeredImage probe = test::renderWith(scene, "bdpt", tinySettings(spp, 99)).image;
    std::vector<std::string> types;
    for (const auto& layer : probe.layers)
        if (layer.name != Film::kOtherLayer && types.size() < 5) types.push_back(layer.name);
    std::vector<std::vector<double>> mlt, bdpt;
    double acceptanceSum = 0;
    for (int seed = 0; seed < seeds; ++seed) {
        RenderSettings st = tinySettings(mpp, 10 + uint64_t(seed));
        st.budgetKind = BudgetKind::MutationsPerPixel;
        RenderResult r = test::renderWith(scene, "mlt", st);
        mlt.push_back(blockMeans(r.image, types));
        acceptanceSum += r.stats.values["acceptance_bidirectional"];
        bdpt.push_back(blockMeans(
            test::renderWith(scene, "bdpt", tinySettings(spp, 700 + uint64_t(seed))).image, types));
    }
    EXPECT_GT(acceptanceSum, 0);
    size_t components = mlt[0].size();
    for (size_t c = 0; c < components; ++c) {
        std::vector<double> a, b;
        for (const auto& v : mlt) a.push_back(v[c]);
        for (const auto& v : bdpt) b.push_back(v[c]);
        auto ma = test::meanAndError(a), mb = test::meanAndError(b);
        size_t group = c / size_t(kBlocksX * kBlocksY);
        std::string what = (group == 0 ? std::string("combined") : types[group - 1]) + " block " +
                           std::to_string(c % size_t(kBlocksX * kBlocksY));
        EXPECT_NEAR(ma.mean, mb.mean, test::twoSampleTolerance(ma, mb, int(components)))
            << sceneName << " " << what << ": mlt " << ma.mean << " +- " << ma.standardError
            << ", bdpt " << mb.mean << " +- " << mb.standardError;
    }
}

TEST(Mlt, ConvergesToBdptPerTypeOnCornell) { expectMltMatchesBdpt("cornell", 64, 64, 10); }

TEST(Mlt, ConvergesToBdptPerTypeOnCornellGlass) {
    expectMltMatchesBdpt("cornell-glass", 64, 64, 10);
}

TEST(Mlt, ConvergesToBdptPerTypeOnPool) { expectMltMatchesBdpt("pool", 64, 64, 10); }

/// b from the bootstrap, with either estimator, against the integral of f* estimated by
/// importance sampling with the exact density of mcmc/independence_mutation.h: independent
/// estimators of the same number.
void expectBootstrapEstimatesTheIntegralOfFStar(StartupEstimator estimator) {
    RenderScene scene = loadScene("cornell-glass");
    Camera camera(resolveCamera(scene.data(), ""), kWidth, kHeight);
    const int seeds = 8, bootstrapSamples = 20000, isSamples = 40000;
    std::vector<double> bootstrap, importance;
    IndependenceMutation independent(scene, camera, 8);
    for (int seed = 0; seed < seeds; ++seed) {
        BootstrapSampler sampler(scene, camera, 8, 30 + uint64_t(seed), estimator);
        std::vector<BootstrapCandidate> candidates;
        uint64_t rays = 0;
        double b = 0;
        for (int i = 0; i < bootstrapSamples; ++i)
            b += sampler.sample(uint64_t(i), candidates, rays);
        bootstrap.push_back(b / bootstrapSamples);
        Rng rng(60 + uint64_t(seed), 0);
        double sum = 0;
        for (int i = 0; i < isSamples; ++i) {
            MarkovPath y;
            if (independent.sample(rng, y, rays)) sum += y.fStar / independent.density(y.vertices);
        }
        importance.push_back(sum / isSamples);
    }
    auto a = test::meanAndError(bootstrap), b = test::meanAndError(importance);
    EXPECT_GT(a.mean, 0);
    EXPECT_NEAR(a.mean, b.mean, test::twoSampleTolerance(a, b))
        << "bootstrap " << a.mean << " +- " << a.standardError << ", importance sampling " << b.mean
        << " +- " << b.standardError;
}

TEST(Mlt, BootstrapEstimatesTheIntegralOfFStar) {
    expectBootstrapEstimatesTheIntegralOfFStar(StartupEstimator::Bidirectional);
}

TEST(Mlt, PathTracerStartupEstimatesTheIntegralOfFStar) {
    expectBootstrapEstimatesTheIntegralOfFStar(StartupEstimator::PathTracer);
}

TEST(Mlt, BlackSceneGivesABlackImage) {
    SceneData s = test::specularBoxScene();
    s.materials[1].emissiveFactor = Rgb(0.0f);  // the only light, switched off
    RenderScene scene(std::move(s));
    RenderSettings st = tinySettings(8, 1);
    st.budgetKind = BudgetKind::MutationsPerPixel;
    RenderResult r = test::renderWith(scene, "mlt", st);
    EXPECT_EQ(r.stats.values["b"], 0.0);
    EXPECT_EQ(r.stats.values["mutations"], 0.0);
    EXPECT_EQ(r.image.combined.width, kWidth);
    EXPECT_EQ(luminance(r.image.combined.mean()), 0.0f);
}

TEST(Mlt, ChainPlanRoundTripsAndRefusesGarbage) {
    ChainPlan plan;
    plan.seed = 7;
    plan.bootstrapSamples = 1000;
    plan.groups = {{"all", 0.25}, {"LDSSE", 1e-3}};
    plan.chains = {{0, 11, 100, 0, {1, 2, 3}}, {1, 12, 200, 1024, std::vector<uint8_t>(64, 9)}};
    std::vector<uint8_t> bytes = serializeChainPlan(plan);
    ChainPlan back = deserializeChainPlan(bytes);
    EXPECT_EQ(back.seed, 7u);
    EXPECT_EQ(back.bootstrapSamples, 1000u);
    ASSERT_EQ(back.groups.size(), 2u);
    EXPECT_EQ(back.groups[1].label, "LDSSE");
    EXPECT_EQ(back.groups[1].b, 1e-3);
    ASSERT_EQ(back.chains.size(), 2u);
    EXPECT_EQ(back.chains[1].stream, 12u);
    EXPECT_EQ(back.chains[1].mutations, 200u);
    EXPECT_EQ(back.chains[1].burnIn, 1024u);
    EXPECT_EQ(back.chains[1].start, plan.chains[1].start);
    EXPECT_EQ(back.mutations(), 300u);
    EXPECT_EQ(serializeChainPlan(back), bytes);
    std::vector<uint8_t> truncated(bytes.begin(), bytes.end() - 5);
    EXPECT_THROW(deserializeChainPlan(truncated), std::invalid_argument);
    std::vector<uint8_t> otherVersion = bytes;
    otherVersion[4] = 99;
    EXPECT_THROW(deserializeChainPlan(otherVersion), std::invalid_argument);
    EXPECT_THROW(deserializeChainPlan(std::vector<uint8_t>(40, 0xab)), std::invalid_argument);
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0);
    EXPECT_THROW(deserializeChainPlan(longer), std::invalid_argument);
}

/// Records the phases it saw; raises the cancel flag once `phase` has run for `after`.
class CancelInPhase : public RenderObserver {
  public:
    CancelInPhase(std::atomic<bool>& cancel, std::string phase, double after)
        : cancel_(cancel), phase_(std::move(phase)), after_(after) {}
    void onProgress(const RenderProgress& p) override {
        if (p.phase != phase_ || cancel_) return;
        if (!started_) {
            started_ = true;
            start_ = std::chrono::steady_clock::now();
        }
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() >=
            after_) {
            cancelledAt_ = std::chrono::steady_clock::now();
            cancel_ = true;
        }
    }
    std::chrono::steady_clock::time_point cancelledAt() const { return cancelledAt_; }
    bool cancelled() const { return cancel_; }

  private:
    std::atomic<bool>& cancel_;
    std::string phase_;
    double after_;
    bool started_ = false;
    std::chrono::steady_clock::time_point start_, cancelledAt_;
};

/// Seconds from the cancel to render() returning by RenderCancelled.
double secondsToCancel(MltSettings settings, const std::string& phase, double budget) {
    RenderScene scene = loadScene("cornell-glass");
    RenderSettings st = tinySettings(budget, 1);
    st.width = 64;
    st.height = 48;
    st.budgetKind = BudgetKind::MutationsPerPixel;
    Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    CancelInPhase observer(cancel, phase, 0.2);
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    MltAlgorithm mlt(settings);
    EXPECT_THROW(mlt.render(ctx), RenderCancelled);
    EXPECT_TRUE(observer.cancelled()) << "the phase " << phase << " never ran long enough";
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - observer.cancelledAt())
        .count();
}

TEST(Mlt, CancelStopsWithinASecondInTheBootstrap) {
    MltSettings s;
    s.bootstrapSamples = 100000000;
    EXPECT_LT(secondsToCancel(s, "bootstrap", 4), 1.0);
}

TEST(Mlt, CancelStopsWithinASecondInTheChains) {
    MltSettings s;
    s.bootstrapSamples = 2000;
    EXPECT_LT(secondsToCancel(s, "render", 1e6), 1.0);
}

TEST(Mlt, RefusesAnOrthographicCamera) {
    SceneData s = test::specularBoxScene();
    s.cameras[0].type = CameraDesc::Type::Orthographic;
    s.cameras[0].ymag = 1;
    RenderScene scene(std::move(s));
    RenderSettings st = tinySettings(4, 1);
    st.budgetKind = BudgetKind::MutationsPerPixel;
    EXPECT_THROW(test::renderWith(scene, "mlt", st), std::invalid_argument);
}

}  // namespace
}  // namespace partita

namespace partita {
namespace {

TEST(Mlt, BootstrapSamplesAreASettingWithALimit) {
    RenderSettings st = tinySettings(4, 1);
    st.budgetKind = BudgetKind::MutationsPerPixel;
    st.parameters.set("bootstrap", 3000);
    const AlgorithmRegistry::Entry& mlt = registeredAlgorithm("mlt");
    EXPECT_EQ(validateJob(mlt, st), "");
    RenderResult r = test::renderWith(loadScene("cornell"), "mlt", st);
    EXPECT_EQ(r.stats.values["bootstrap_samples"], 3000.0);
    st.parameters.set("bootstrap", RenderLimits{}.maxBootstrapSamples + 1);
    EXPECT_NE(validateJob(mlt, st).find("exceeds the limit"), std::string::npos);
    // 0 is the start-up rule's count (mcmc/startup_rule.h), a value like any other.
    st.parameters.set("bootstrap", 0);
    EXPECT_EQ(validateJob(mlt, st), "");
}

}  // namespace
}  // namespace partita

namespace partita {
namespace {

TEST(Mlt, ATimeBudgetShorterThanTheBootstrapStillEnds) {
    RenderSettings st = tinySettings(0.01, 1);
    st.budgetKind = BudgetKind::Seconds;
    st.parameters.set("bootstrap", 200000);
    auto start = std::chrono::steady_clock::now();
    RenderResult r = test::renderWith(loadScene("cornell"), "mlt", st);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GT(r.stats.values["mutations"], 0.0);
    EXPECT_LT(seconds, r.stats.values["bootstrap_seconds"] + 2.0);
}

TEST(Mlt, StuckChainsAreCountedForEveryMcmcAlgorithm) {
    // A chain is stuck when it moved in none of the last half of its mutations (issue #22 2).
    // With Veach's mutations nothing sticks on the diffuse box, and every MCMC algorithm says so,
    // per partition too. 32 chains of ~384 mutations: a chain of a few dozen (the default 256
    // chains at 8 mpp) can go a dozen rejections in a row on a bright path by chance, and the
    // statistic then counts it, though nothing is wrong.
    RenderScene scene = loadScene("cornell");
    for (const char* algorithm : {"mlt", "partitioned", "guided"}) {
        RenderSettings st = tinySettings(64, 1);
        st.budgetKind = BudgetKind::MutationsPerPixel;
        st.parameters.set("bootstrap", 4000);
        st.parameters.set("chains", 32);
        // Every partition with chains (estimators=auto sends the box's per pixel).
        if (std::string(algorithm) != "mlt") st.parameters.set("estimators", std::string("chains"));
        RenderResult r = test::renderWith(scene, algorithm, st);
        ASSERT_EQ(r.stats.values.count("stuck_chains"), 1u) << algorithm;
        EXPECT_EQ(r.stats.values["stuck_chains"], 0.0) << algorithm;
        ASSERT_EQ(r.stats.values.count("type_bound_chains"), 1u) << algorithm;
        EXPECT_GT(r.stats.values["chains"], 0.0) << algorithm;
        if (std::string(algorithm) != "mlt") {
            EXPECT_EQ(r.stats.values.count("partition_0_stuck_chains"), 1u) << algorithm;
        }
    }
    // The negative control: only the caustic perturbation, which applies to no path of a box
    // without specular surfaces, so no chain ever moves and every one is stuck.
    MltSettings causticOnly;
    causticOnly.bootstrapSamples = 4000;
    causticOnly.mutations.bidirectionalWeight = 0;
    causticOnly.mutations.lensWeight = 0;
    causticOnly.mutations.multiChainWeight = 0;
    causticOnly.mutations.largeStepRate = 0;  // the independence mutation applies to every path
    RenderSettings st = tinySettings(8, 1);
    st.budgetKind = BudgetKind::MutationsPerPixel;
    Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    RenderResult stuck = MltAlgorithm(causticOnly).render(ctx);
    EXPECT_GT(stuck.stats.values["chains"], 0.0);
    EXPECT_EQ(stuck.stats.values["stuck_chains"], stuck.stats.values["chains"]);
    EXPECT_EQ(stuck.stats.values["type_bound_chains"], stuck.stats.values["chains"]);
    // With Veach's mutations the chains on the box change their path's length, and so its type:
    // some leave their start's type (fixed seed: 27 of 48 keep it at this short budget).
    RenderResult moving = test::renderWith(scene, "mlt", st);
    EXPECT_LT(moving.stats.values["type_bound_chains"], moving.stats.values["chains"]);
    EXPECT_GT(moving.stats.values["type_bound_chains"], 0.0);
}

TEST(Mlt, ATimeBudgetsBootstrapStopsAtItsShare) {
    // 2^30 samples would take hours; with a time budget the bootstrap stops after its share
    // (startup_share, 0.1 by default) and b counts the samples that ran (issue #25 2).
    RenderSettings st = tinySettings(1, 1);
    st.budgetKind = BudgetKind::Seconds;
    st.budget = 1;
    st.parameters.set("bootstrap", uint64_t(1) << 30);
    RenderResult r = test::renderWith(loadScene("cornell"), "mlt", st);
    EXPECT_GT(r.stats.values["bootstrap_samples"], 0.0);
    EXPECT_LT(r.stats.values["bootstrap_samples"], double(uint64_t(1) << 24));
    EXPECT_GT(r.stats.values["b"], 0.0);
    EXPECT_GT(r.stats.values["mutations"], 0.0) << "the chains got the rest";
}

}  // namespace
}  // namespace partita
