// mlt's direct light apart (issue #22 1, integrators/mlt/direct_light.h): with "direct" =
// per-pixel the image agrees with bdpt per type and combined (on cornell-glass, cornell-point and
// a scene under an environment map; tolerances from the spread over independent seeds on both
// sides); the per-pixel part and the chains have no type in common; "direct" = chains is the
// image of the code path before the split, bit for bit; the thread count and sharding do not
// change the image; a time budget's direct light stops at its share.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <random>

#include "camera.h"
#include "environment_map.h"
#include "film.h"
#include "gltf/gltf_loader.h"
#include "image_bits.h"
#include "integrators/mlt/direct_light.h"
#include "integrators/mlt/mlt_integrator.h"
#include "mcmc/bootstrap.h"
#include "mcmc/chain_render.h"
#include "mcmc/chain_runner.h"
#include "progress_reporter.h"
#include "render_helpers.h"
#include "renderer.h"
#include "scene_builders.h"
#include "shard/sharded_render.h"
#include "thread_pool.h"

namespace partita {
namespace {

constexpr int kWidth = 16, kHeight = 12, kBlocksX = 2, kBlocksY = 2;

RenderScene loadScene(const std::string& name) {
    return RenderScene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/" + name + "/" + name + ".gltf"));
}

/// A Lambert floor, a glass and a mirror sphere under an environment map with a small bright
/// "sun": the sky seen directly (L E) and through the spheres (L S+ E), direct light (L D E,
/// L D S+ E) and caustics and interreflections for the chains.
SceneData environmentScene() {
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.8f)), test::glassMaterial(1.5f),
                   test::mirrorMaterial()};
    s.meshes.push_back(test::quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 0));  // normal +y
    s.meshes.push_back(test::sphere({-0.35f, 0.3f, 0}, 0.3f, 1, 16, 32));
    s.meshes.push_back(test::sphere({0.4f, 0.25f, -0.2f}, 0.25f, 2, 16, 32));
    Image sky(32, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            sky.set(x, y, (y == 3 && x == 15) ? Rgb(300.0f) : Rgb(0.3f, 0.4f, 0.6f + 0.02f * y));
    s.environment = std::make_shared<EnvironmentMap>(std::move(sky), 20.0f);
    s.cameras.push_back(test::lookAtCamera({0, 1.0f, 2.2f}, {0, 0.25f, 0}, 0.9f));
    return s;
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

RenderSettings mltSettings(double mpp, uint64_t seed, const std::string& direct,
                           uint64_t directSpp = 16) {
    RenderSettings st = tinySettings(mpp, seed);
    st.budgetKind = BudgetKind::MutationsPerPixel;
    st.parameters.set("bootstrap", 20000);
    st.parameters.set("direct", direct);
    st.parameters.set("direct_spp", directSpp);
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

/// mlt with the direct light per pixel at `mpp` and spp / 2 direct samples per pixel against
/// bdpt at `spp`, `seeds` independent seeds each, per image quarter combined and for bdpt's
/// three brightest direct and three brightest other types. Negative controls, run by hand: the
/// chains left unrestricted fail on cornell-glass and cornell-point, the direct part's MIS
/// weights left out on cornell-glass and the environment scene.
void expectDirectApartMatchesBdpt(const RenderScene& scene, const std::string& name, double mpp,
                                  double spp, int seeds, bool autoSplit = false) {
    LayeredImage probe = test::renderWith(scene, "bdpt", tinySettings(4 * spp, 99)).image;
    std::vector<std::string> types;
    int direct = 0, indirect = 0;
    for (const auto& layer : probe.layers) {
        PathType t;
        if (layer.name == Film::kOtherLayer || !PathType::parse(layer.name, t)) continue;
        int& count = isDirectLightType(t) ? direct : indirect;
        if (count < 3) {
            types.push_back(layer.name);
            ++count;
        }
    }
    ASSERT_GT(direct, 0) << name;
    ASSERT_GT(indirect, 0) << name;
    std::vector<std::vector<double>> mlt, bdpt;
    for (int seed = 0; seed < seeds; ++seed) {
        RenderResult r = test::renderWith(
            scene, "mlt",
            mltSettings(mpp, 10 + uint64_t(seed), "per-pixel", autoSplit ? 0 : uint64_t(spp / 2)));
        EXPECT_EQ(r.stats.labels["direct"], "per-pixel");
        if (!autoSplit) {
            EXPECT_EQ(r.stats.values["direct_spp"], spp / 2);
        } else {
            EXPECT_GE(r.stats.values["direct_spp"], 2.0);
            EXPECT_GT(r.stats.values["direct_variance"], 0.0);
            EXPECT_GT(r.stats.values["chain_error"], 0.0);
        }
        EXPECT_GT(r.stats.values["direct_share"], 0.0);
        mlt.push_back(blockMeans(r.image, types));
        bdpt.push_back(blockMeans(
            test::renderWith(scene, "bdpt", tinySettings(spp, 700 + uint64_t(seed))).image, types));
    }
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
            << name << " " << what << ": mlt " << ma.mean << " +- " << ma.standardError << ", bdpt "
            << mb.mean << " +- " << mb.standardError;
    }
}

TEST(MltDirect, AgreesWithBdptPerTypeOnCornellGlass) {
    expectDirectApartMatchesBdpt(loadScene("cornell-glass"), "cornell-glass", 256, 64, 16);
}

TEST(MltDirect, AgreesWithBdptPerTypeOnCornellPoint) {
    // The point light seen directly (L E) only light tracing renders: the per-pixel part
    // light-traces it.
    expectDirectApartMatchesBdpt(loadScene("cornell-point"), "cornell-point", 256, 64, 16);
}

TEST(MltDirect, AgreesWithBdptPerTypeUnderAnEnvironmentMap) {
    expectDirectApartMatchesBdpt(RenderScene(environmentScene()), "environment", 256, 64, 16);
}

TEST(MltDirect, AStronglyDampedTargetStillAgreesWithBdpt) {
    // The chains' target damps short edges (path/short_edge_damping.h) and the bootstrap's b*
    // integrates the same damped target, so the image does not change, only where the chains
    // spend their time. With eps half the scene's diagonal nearly every path is damped, many
    // by orders of magnitude: b* falls well below b, and the image still agrees with bdpt per
    // type. (Negative control, run by hand: the bootstrap's weights left undamped fail here.)
    RenderScene scene = loadScene("cornell-glass");
    const double b =
        test::renderWith(scene, "mlt", mltSettings(16, 3, "per-pixel")).stats.values.at("b");
    scene.setShortEdge(0.5f * length(scene.bounds().diagonal()));
    const double damped =
        test::renderWith(scene, "mlt", mltSettings(16, 3, "per-pixel")).stats.values.at("b");
    EXPECT_LT(damped, 0.5 * b) << "the damping acts";
    expectDirectApartMatchesBdpt(scene, "cornell-glass damped", 256, 64, 16);
}

TEST(MltDirect, TheSplitRuleAgreesWithBdptOnCornellGlass) {
    // The samples per pixel the rule chooses (from the chains' and the pilot's measurements, the
    // pilot's samples not in the image) leave the image unbiased.
    expectDirectApartMatchesBdpt(loadScene("cornell-glass"), "cornell-glass auto", 256, 64, 16,
                                 true);
}

TEST(MltDirect, TheSplitRuleMinimisesTheModelError) {
    // E(n) = V_d / n + A_c / T_c with the chains' cost T_c fixed and the direct light's n c_d:
    // for the total T = T_c + n c_d the rule's n is the best split, so no other split of the
    // same total does better (checked on a grid of totals around it).
    const double vd = 40, cd = 300, ec = 0.02, tc = 1e6;
    const uint64_t n = neymanDirectSpp(vd, cd, ec, tc, 1, 1 << 20);
    EXPECT_NEAR(double(n), std::ceil(std::sqrt(vd * tc / (ec * cd))), 0.0);
    const double total = tc + double(n) * cd, ac = ec * tc;
    auto error = [&](double directCost) {
        return vd * cd / directCost + ac / (total - directCost);
    };
    const double best = error(double(n) * cd);
    for (double f = 0.05; f < 0.95; f += 0.01) EXPECT_LE(best, error(f * total) * (1 + 1e-3)) << f;
    // The share form is the same rule.
    EXPECT_NEAR(neymanDirectShare(vd, cd, ec, tc) * total, double(n) * cd, cd);
    // Nothing measured: the least; no chain error: everything to the direct light.
    EXPECT_EQ(neymanDirectSpp(vd, cd, 0, tc, 3, 100), 3u);
    EXPECT_EQ(neymanDirectSpp(vd, cd, ec, tc, 3, 100), 100u);
    EXPECT_EQ(neymanDirectShare(vd, cd, 0, tc), 1.0);
    EXPECT_EQ(neymanDirectShare(0, cd, ec, tc), 0.0);
}

TEST(MltDirect, TheRuleReadsTheVarianceFromThePilotAndItsOwnSamples) {
    // Before the direct light has samples in both halves: the pilot's V_d. After: pooled by
    // sample counts with the halves' per-sample variance (here one grey pixel: half A 3 samples
    // summing to 3, half B 1 sample of 5: per-sample variance (1 - 5)^2 3 / 4 = 12).
    HalfSplitError own;
    Image sums(1, 1);
    sums.rgb.assign(3, 3.0f);
    own.addRun(sums, 3, true);
    EXPECT_EQ(pooledDirectVariance(7.0, own), 7.0);
    sums.rgb.assign(3, 8.0f);
    own.addRun(sums, 1, false);
    EXPECT_NEAR(own.perSampleLuminanceVariance(), 12.0, 1e-4);
    EXPECT_NEAR(pooledDirectVariance(7.0, own), (2 * 7.0 + 4 * 12.0) / 6, 1e-4);
}

TEST(MltDirect, ClassifiesTheDirectLightTypes) {
    for (const char* s : {"LE", "LSE", "LSSSE", "LDE", "LDSE", "LDSSSE"}) {
        PathType t;
        ASSERT_TRUE(PathType::parse(s, t));
        EXPECT_TRUE(isDirectLightType(t)) << s;
    }
    for (const char* s : {"LDDE", "LSDE", "LDSDE", "LSSDE", "LDDSE", "LDSDSE", "LSDSE"}) {
        PathType t;
        ASSERT_TRUE(PathType::parse(s, t));
        EXPECT_FALSE(isDirectLightType(t)) << s;
    }
    // The chains' restriction is the complement, on every type of up to 8 scattering vertices.
    PathRestriction chains = indirectLightOnly();
    int directTypes = 0;
    for (int count = 0; count <= 8; ++count)
        for (uint64_t mask = 0; mask < (uint64_t(1) << count); ++mask) {
            PathType t;
            ASSERT_TRUE(PathType::fromBits(mask, count, t));
            EXPECT_NE(chains(t), isDirectLightType(t)) << t.toString();
            directTypes += isDirectLightType(t);
        }
    EXPECT_EQ(directTypes, 1 + 2 * 8);  // L E, and per length L S^k E and L D S^(k-1) E
}

TEST(MltDirect, PerPixelPartAndChainsHaveNoTypeInCommon) {
    for (const char* name : {"cornell-glass", "cornell-point"}) {
        RenderScene scene = loadScene(name);
        RenderSettings st = mltSettings(16, 3, "per-pixel");
        Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
        ThreadPool pool(2);
        std::atomic<bool> cancel{false};
        RenderObserver observer;
        RenderContext ctx{scene, camera, st, pool, cancel, observer};
        MltSettings settings;
        settings.bootstrapSamples = 20000;
        MltStart start = startMlt(ctx, settings);
        ASSERT_TRUE(start.directApart);
        EXPECT_GT(start.plan.chains.size(), 0u) << name;
        // b splits into the direct part's and the chains'.
        EXPECT_NEAR(start.bDirect + start.plan.groups[0].b, start.bootstrap.b,
                    1e-6 * start.bootstrap.b);
        EXPECT_GT(start.bDirect, 0) << name;

        DirectLightRenderer direct(ctx);
        direct.renderPass({0, 8}, nullptr);
        LayeredImage d = direct.film().resolve(1.0f / 8, 1024);
        ASSERT_FALSE(d.layers.empty());
        for (const ImageLayer& layer : d.layers) {
            PathType t;
            ASSERT_TRUE(PathType::parse(layer.name, t)) << layer.name;
            EXPECT_TRUE(isDirectLightType(t)) << name << ": " << layer.name;
        }
        start.plan.layers = TypeLayers::every();  // every type a layer: none hides in "other"
        ChainRunner runner(
            ctx, start.plan, [&](uint32_t) { return makeMltMutations(ctx, settings); },
            [](uint32_t) { return indirectLightOnly(); });
        ProgressReporter progress(observer, "render", "mutations", 0);
        runner.run(progress, 0);
        ASSERT_EQ(start.plan.groups.size(), 2u);  // the two halves of the chains
        for (uint32_t g = 0; g < 2; ++g) {
            LayeredImage c = runner.film(g).resolve(1.0f, 1024);
            ASSERT_FALSE(c.layers.empty());
            for (const ImageLayer& layer : c.layers) {
                PathType t;
                ASSERT_TRUE(PathType::parse(layer.name, t)) << layer.name;
                EXPECT_FALSE(isDirectLightType(t)) << name << ": " << layer.name;
            }
        }
    }
}

TEST(MltDirect, TheChainHalvesShareOneLayeredFilm) {
    // The runner's AllAndHalf layout (issue #24: one layered film for both halves, not two)
    // holds exactly what the per-group films hold: film 0 is their sum bit for bit, film 1 the
    // odd chains' combined image with no type buffer, and the halves' error is the same.
    RenderScene scene = loadScene("cornell-glass");
    RenderSettings st = mltSettings(16, 3, "per-pixel");
    Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    MltSettings settings;
    settings.bootstrapSamples = 20000;
    const MltStart start = startMlt(ctx, settings);
    ASSERT_EQ(start.plan.groups.size(), 2u);
    auto run = [&](ChainRunner::FilmLayout layout) {
        auto runner = std::make_unique<ChainRunner>(
            ctx, start.plan, [&](uint32_t) { return makeMltMutations(ctx, settings); },
            [](uint32_t) { return indirectLightOnly(); }, 1024, layout);
        ProgressReporter progress(observer, "render", "mutations", 0);
        runner->run(progress, 0);
        return runner;
    };
    auto perGroup = run(ChainRunner::FilmLayout::PerGroup);
    auto allAndHalf = run(ChainRunner::FilmLayout::AllAndHalf);

    Film sum(st.width, st.height, start.plan.layers);
    sum.merge(perGroup->film(0));
    sum.merge(perGroup->film(1));
    test::expectSameBits(sum.resolve(1.0f, 1024), allAndHalf->film(0).resolve(1.0f, 1024));
    EXPECT_TRUE(allAndHalf->film(1).layers().keepsNone());
    EXPECT_LE(allAndHalf->film(1).maxBuffersPerTile(), 1u);
    const Image odd = perGroup->film(1).resolveCombined(1.0f);
    EXPECT_EQ(odd.rgb, allAndHalf->film(1).resolveCombined(1.0f).rgb);

    // The error of the halves, from the two per-group films directly.
    const uint64_t even = perGroup->mutationsDone(0), oddDone = perGroup->mutationsDone(1);
    ASSERT_GT(even, 0u);
    ASSERT_GT(oddDone, 0u);
    const double b = start.plan.groups[0].b, pixels = double(st.width) * st.height;
    const Image ia = perGroup->film(0).resolveCombined(float(b * pixels / double(even)));
    const Image ib = perGroup->film(1).resolveCombined(float(b * pixels / double(oddDone)));
    double expected = 0;
    for (size_t i = 0; i + 2 < ia.rgb.size(); i += 3) {
        const double d = double(luminance(Rgb(ia.rgb[i], ia.rgb[i + 1], ia.rgb[i + 2]))) -
                         double(luminance(Rgb(ib.rgb[i], ib.rgb[i + 1], ib.rgb[i + 2])));
        expected += d * d / 4;
    }
    ASSERT_GT(expected, 0);
    const double error = chainHalvesError(allAndHalf->film(0), allAndHalf->film(1), even, oddDone,
                                          b, st.width, st.height);
    // Only float rounding apart: film 0 less film 1 is resolved in float, not in fixed point.
    EXPECT_NEAR(error, expected, 1e-4 * expected);
}

TEST(MltDirect, ChainsModeIsTheImageOfTheCodePathBeforeTheSplit) {
    // What MltAlgorithm::render did before "direct" existed: the bootstrap, the plan of all
    // candidates with the bootstrap's b, unrestricted chains, group 0's film.
    for (const char* name : {"cornell-glass", "cornell-point"}) {
        RenderScene scene = loadScene(name);
        RenderSettings st = mltSettings(8, 5, "chains");
        RenderResult now = test::renderWith(scene, "mlt", st);
        EXPECT_EQ(now.stats.labels["direct"], "chains");
        EXPECT_EQ(now.stats.values.count("direct_share"), 0u);

        Camera camera(resolveCamera(scene.data(), ""), st.width, st.height);
        ThreadPool pool(2);
        std::atomic<bool> cancel{false};
        RenderObserver observer;
        RenderContext ctx{scene, camera, st, pool, cancel, observer};
        MltSettings settings;
        settings.bootstrapSamples = 20000;
        settings.direct = "chains";  // the independence mutation proposes every length
        BootstrapSampler sampler(scene, camera, st.maxDepth, st.seed);
        BootstrapResult bootstrap = runBootstrap(ctx, sampler, settings.bootstrapSamples);
        uint64_t mutations = uint64_t(st.budget * st.width * st.height);
        int chains = int(std::min<uint64_t>(uint64_t(settings.chains),
                                            mutations / settings.minMutationsPerChain));
        ChainPlan plan = planMltChains(ctx, sampler, bootstrap, chains, mutations);
        ChainRunner runner(ctx, plan, [&](uint32_t) { return makeMltMutations(ctx, settings); });
        runChainsWithPreviews(ctx, runner, plan, 0, {}, {});
        test::expectSameBits(now.image, runner.resolveGroup(0, nullptr));
        EXPECT_EQ(now.stats.values["b"], bootstrap.b);
    }
}

TEST(MltDirect, ThreadCountAndShardsDoNotChangeTheImage) {
    for (const char* name : {"cornell-point", "cornell-glass"})
        for (uint64_t directSpp : {uint64_t(5), uint64_t(0)}) {
            SCOPED_TRACE(testing::Message() << name << ", direct_spp " << directSpp);
            RenderScene scene = loadScene(name);
            RenderSettings st = mltSettings(6, 7, "per-pixel", directSpp);
            const RenderResult two = test::renderWith(scene, "mlt", st, 2);
            const RenderResult one = test::renderWith(scene, "mlt", st, 1);
            test::expectSameBits(one.image, two.image);
            for (uint32_t shards : {2u, 3u}) {
                ThreadPool pool(shards == 2 ? 1 : 2);
                std::atomic<bool> cancel{false};
                RenderObserver observer;
                ShardEnvironment env{scene, pool, cancel, observer};
                ShardPlan plan = planShardedRender(env, "mlt", st, shards, "scene", 1);
                plan = deserializeShardPlan(serializeShardPlan(plan));
                std::vector<ShardResult> results;
                for (uint32_t i = 0; i < plan.shards; ++i)
                    results.push_back(deserializeShardResult(
                        serializeShardResult(renderPlannedShard(env, plan, i))));
                std::shuffle(results.begin(), results.end(), std::mt19937(shards));
                ShardMerger merger(plan);
                for (const ShardResult& r : results) EXPECT_TRUE(merger.add(r));
                ASSERT_TRUE(merger.complete());
                const RenderResult merged = resolveShardedRender(env, plan, merger.work());
                test::expectSameBits(merged.image, two.image);
                EXPECT_EQ(merged.stats.values.at("rays"), two.stats.values.at("rays"));
                EXPECT_EQ(merged.stats.values.at("direct_spp"), two.stats.values.at("direct_spp"));
                if (directSpp > 0) {
                    EXPECT_EQ(merged.stats.values.at("direct_spp"), 5.0);
                }
                EXPECT_EQ(merged.stats.values.at("mutations"), two.stats.values.at("mutations"));
                EXPECT_EQ(merged.stats.values.at("direct_share"),
                          two.stats.values.at("direct_share"));
            }
        }
}

TEST(MltDirect, ATimeBudgetIsSplitByTheRule) {
    RenderSettings st = tinySettings(1, 1);
    st.budgetKind = BudgetKind::Seconds;
    st.parameters.set("bootstrap", 4000);
    RenderResult r = test::renderWith(loadScene("cornell-glass"), "mlt", st);
    EXPECT_GE(r.stats.values["direct_spp"], 1.0);
    EXPECT_GT(r.stats.values["direct_time_share"], 0.0);
    EXPECT_LT(r.stats.values["direct_time_share"], 1.0);
    EXPECT_GT(r.stats.values["mutations"], 0.0);
    EXPECT_LT(r.stats.values["seconds"], 3.0);
}

TEST(MltDirect, ATimeBudgetsDirectLightStopsAtItsShare) {
    RenderSettings st = tinySettings(1, 1);
    st.budgetKind = BudgetKind::Seconds;
    st.parameters.set("bootstrap", 4000);
    st.parameters.set("direct_spp", uint64_t(1) << 20);  // hours at this size
    RenderResult r = test::renderWith(loadScene("cornell"), "mlt", st);
    EXPECT_GE(r.stats.values["direct_spp"], 1.0);
    EXPECT_LT(r.stats.values["direct_spp"], double(uint64_t(1) << 20));
    EXPECT_GT(r.stats.values["mutations"], 0.0) << "the chains got the rest";
    EXPECT_LT(r.stats.values["seconds"], 3.0);
}

TEST(MltDirect, OnlyDirectLightRunsNoChains) {
    // A Lambert plane under a point light: every path is L D E, all of it per pixel; the chains
    // have nothing (b = 0) and the image is the direct part's.
    SceneData s;
    s.materials = {test::lambertMaterial(Rgb(0.7f))};
    s.meshes.push_back(test::quad({-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 0));
    PunctualLightDesc light;
    light.type = PunctualLightDesc::Type::Point;
    light.intensity = 5;
    light.position = {0, 1.5f, 0};
    s.lights.push_back(light);
    s.cameras.push_back(test::lookAtCamera({0, 1.0f, 2.0f}, {0, 0, 0}, 0.9f));
    RenderScene scene(std::move(s));
    RenderResult r = test::renderWith(scene, "mlt", mltSettings(4, 1, "per-pixel"));
    EXPECT_EQ(r.stats.values["b"], 0.0);
    EXPECT_EQ(r.stats.values["mutations"], 0.0);
    EXPECT_GT(luminance(r.image.combined.mean()), 0.0f);
    ASSERT_EQ(r.image.layers.size(), 1u);
    EXPECT_EQ(r.image.layers[0].name, "LDE");
}

}  // namespace
}  // namespace partita
