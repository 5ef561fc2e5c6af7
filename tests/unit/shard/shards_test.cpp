// One job as shards (shard/): the merge of N shards, in any order and with a shard given twice,
// is bit-identical to the one-process render with the same settings, for every algorithm that
// can be sharded; results of another plan, another shard count, damaged files and clashing
// shard indices are refused with a clear error; settings that cannot be sharded are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <random>

#include "gltf/gltf_loader.h"
#include "image_bits.h"
#include "params/job_parameters.h"
#include "render_helpers.h"
#include "shard/sharded_render.h"

namespace partita {
namespace {

RenderScene loadScene(const std::string& name) {
    return RenderScene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/" + name + "/" + name + ".gltf"));
}

using test::expectSameBits;

struct Harness {
    explicit Harness(const RenderScene& scene, int threads = 2)
        : pool(threads), env{scene, pool, cancel, observer} {}
    ThreadPool pool;
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    ShardEnvironment env;
};

struct Case {
    const char* algorithm;
    BudgetKind kind;
    double budget;
    const char* estimators = nullptr;  // partitioned's and guided's (default: auto)
};

RenderSettings settingsOf(const Case& c) {
    RenderSettings s;
    s.width = 16;
    s.height = 12;
    s.budgetKind = c.kind;
    s.budget = c.budget;
    s.seed = 7;
    s.previewIntervalSeconds = 0;
    s.maxTypeLayers = 4;  // bounded type layers (issue #24): far fewer than the scene's types
    const auto& declared = registeredAlgorithm(c.algorithm).parameters;
    if (std::any_of(declared.begin(), declared.end(),
                    [](const ParameterSpec& p) { return p.name == "bootstrap"; }))
        s.parameters.set("bootstrap", 4000);
    if (c.estimators) s.parameters.set("estimators", std::string(c.estimators));
    return s;
}

class ShardedRender : public testing::TestWithParam<Case> {};

TEST_P(ShardedRender, MergeIsBitIdenticalToOneProcessForAnyShardCountAndOrder) {
    const Case c = GetParam();
    RenderScene scene = loadScene("cornell-glass");
    const RenderSettings settings = settingsOf(c);
    const RenderResult one = test::renderWith(scene, c.algorithm, settings, 2);
    for (uint32_t shards : {1u, 2u, 7u}) {
        SCOPED_TRACE(testing::Message() << shards << " shards");
        Harness h(scene, shards == 2 ? 1 : 2);  // the thread count must not matter either
        ShardPlan plan = planShardedRender(h.env, c.algorithm, settings, shards, "scene", 1);
        ASSERT_EQ(plan.shards, shards);
        // Through the file formats, as the shards of a cluster job travel.
        plan = deserializeShardPlan(serializeShardPlan(plan));
        std::vector<ShardResult> results;
        for (uint32_t i = 0; i < plan.shards; ++i)
            results.push_back(
                deserializeShardResult(serializeShardResult(renderPlannedShard(h.env, plan, i))));
        std::vector<size_t> order(results.size());
        for (size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::shuffle(order.begin(), order.end(), std::mt19937(shards));
        ShardMerger merger(plan);
        for (size_t i : order) EXPECT_TRUE(merger.add(results[i]));
        EXPECT_FALSE(merger.add(results[order.front()]));  // a retried shard: merged once
        ASSERT_TRUE(merger.complete());
        const RenderResult merged = resolveShardedRender(h.env, plan, merger.work());
        expectSameBits(merged.image, one.image);
        EXPECT_EQ(merged.stats.values.at("rays"), one.stats.values.at("rays"));
    }
    // cornell-glass has thousands of types: pt, bdpt and mlt keep 4 of them (chosen once, for
    // every shard and thread count alike) and sum the rest into "other".
    if (std::string(c.algorithm) == "pt" || std::string(c.algorithm) == "bdpt" ||
        std::string(c.algorithm) == "mlt") {
        ASSERT_EQ(one.image.layers.size(), 5u);
        EXPECT_EQ(one.image.layers.back().name, Film::kOtherLayer);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Algorithms, ShardedRender,
    testing::Values(Case{"pt", BudgetKind::SamplesPerPixel, 9},
                    Case{"bdpt", BudgetKind::SamplesPerPixel, 7},
                    Case{"mlt", BudgetKind::MutationsPerPixel, 6},
                    // Every partition with chains: shards split them.
                    Case{"partitioned", BudgetKind::MutationsPerPixel, 6, "chains"},
                    // Every partition per pixel: shards split the samples.
                    Case{"partitioned", BudgetKind::MutationsPerPixel, 9, "per-pixel"},
                    // The default (auto): every partition per pixel here (the path tracer's, 10 samples).
                    Case{"partitioned", BudgetKind::MutationsPerPixel, 24},
                    Case{"guided", BudgetKind::MutationsPerPixel, 6, "chains"},
                    Case{"guided", BudgetKind::MutationsPerPixel, 24}),
    [](const auto& info) {
        std::string name = info.param.algorithm;
        if (info.param.estimators) name += "_" + std::string(info.param.estimators);
        std::replace(name.begin(), name.end(), '-', '_');
        return name;
    });

TEST(ShardedRender, BdptSplatBatchesOfALargeImageAreTheSameForAnyThreadsAndShards) {
    // bdpt adds its light-tracing splats batch by batch (256 tiles); an image of more tiles than
    // that must still give the same bits for any thread count and shard split.
    RenderScene scene = loadScene("cornell");
    RenderSettings settings = settingsOf({"bdpt", BudgetKind::SamplesPerPixel, 2});
    settings.width = 288;  // 18 x 15 = 270 tiles
    settings.height = 240;
    settings.maxDepth = 4;
    const RenderResult one = test::renderWith(scene, "bdpt", settings, 2);
    expectSameBits(test::renderWith(scene, "bdpt", settings, 1).image, one.image);
    Harness h(scene, 1);
    const ShardPlan plan = planShardedRender(h.env, "bdpt", settings, 2, "scene", 1);
    ShardMerger merger(plan);
    for (uint32_t i = 0; i < plan.shards; ++i)
        EXPECT_TRUE(merger.add(renderPlannedShard(h.env, plan, i)));
    expectSameBits(resolveShardedRender(h.env, plan, merger.work()).image, one.image);
}

TEST(ShardedRender, MismatchedShardsAreRefused) {
    RenderScene scene = loadScene("cornell-glass");
    Harness h(scene);
    const RenderSettings settings = settingsOf({"pt", BudgetKind::SamplesPerPixel, 4});
    const ShardPlan plan = planShardedRender(h.env, "pt", settings, 3, "scene", 1);
    RenderSettings otherSeed = settings;
    otherSeed.seed = 8;
    const ShardPlan other = planShardedRender(h.env, "pt", otherSeed, 3, "scene", 1);
    ASSERT_NE(plan.id(), other.id());

    ShardMerger merger(plan);
    ShardResult foreign = renderPlannedShard(h.env, other, 0);
    EXPECT_THROW(merger.add(foreign), std::invalid_argument);  // another job's shard
    ShardResult mine = renderPlannedShard(h.env, plan, 1);
    ShardResult wrongCount = renderPlannedShard(h.env, plan, 1);
    wrongCount.shards = 4;
    EXPECT_THROW(merger.add(wrongCount), std::invalid_argument);
    EXPECT_TRUE(merger.add(mine));
    ShardResult clash = renderPlannedShard(h.env, plan, 2);
    clash.shard = 1;  // shard 2's work claiming to be shard 1
    EXPECT_THROW(merger.add(clash), std::invalid_argument);
    EXPECT_EQ(merger.mergedCount(), 1u);
    EXPECT_EQ(merger.missing(), (std::vector<uint32_t>{0, 2}));
    EXPECT_THROW(renderPlannedShard(h.env, plan, 3), std::invalid_argument);

    // Damaged files: every truncation and a flipped byte anywhere fail the checksum.
    std::vector<uint8_t> bytes = serializeShardResult(mine);
    for (size_t cut : {size_t(0), size_t(7), bytes.size() / 2, bytes.size() - 1})
        EXPECT_THROW(deserializeShardResult(std::span(bytes).first(cut)), std::invalid_argument);
    std::vector<uint8_t> flipped = bytes;
    flipped[bytes.size() / 3] ^= 1;
    EXPECT_THROW(deserializeShardResult(flipped), std::invalid_argument);
    std::vector<uint8_t> otherVersion = bytes;
    otherVersion[4] ^= 0x10;  // the version field
    EXPECT_THROW(deserializeShardResult(otherVersion), std::invalid_argument);
    std::vector<uint8_t> planBytes = serializeShardPlan(plan);
    EXPECT_THROW(deserializeShardPlan(std::span(planBytes).first(planBytes.size() - 1)),
                 std::invalid_argument);
    EXPECT_THROW(deserializeShardPlan(bytes), std::invalid_argument);  // a shard is not a plan
}

TEST(ShardedRender, WhatCannotBeShardedIsRefused) {
    RenderScene scene = loadScene("cornell-glass");
    Harness h(scene);
    RenderSettings timed = settingsOf({"pt", BudgetKind::Seconds, 1});
    EXPECT_THROW(planShardedRender(h.env, "pt", timed, 2, "scene", 1), std::invalid_argument);
    for (const char* mcmc : {"mlt", "partitioned", "guided"}) {
        RenderSettings mcmcTimed = settingsOf({mcmc, BudgetKind::Seconds, 1});
        EXPECT_THROW(planShardedRender(h.env, mcmc, mcmcTimed, 2, "scene", 1),
                     std::invalid_argument)
            << mcmc;
    }
    RenderSettings spp = settingsOf({"pt", BudgetKind::SamplesPerPixel, 3});
    EXPECT_THROW(planShardedRender(h.env, "pt", spp, 0, "scene", 1), std::invalid_argument);
    EXPECT_THROW(planShardedRender(h.env, "warp", spp, 2, "scene", 1), std::invalid_argument);
    // More shards than samples per pixel: clamped, every shard has work.
    EXPECT_EQ(planShardedRender(h.env, "pt", spp, 10, "scene", 1).shards, 3u);
}

TEST(ShareRange, CoversEverythingOnceAndEvenly) {
    for (uint64_t total : {0ull, 1ull, 5ull, 64ull, 1001ull})
        for (uint32_t parts : {1u, 2u, 7u}) {
            uint64_t next = 0, smallest = UINT64_MAX, largest = 0;
            for (uint32_t p = 0; p < parts; ++p) {
                ShareRange r = shareRange(total, parts, p);
                EXPECT_EQ(r.first, next);
                next = r.end;
                smallest = std::min(smallest, r.end - r.first);
                largest = std::max(largest, r.end - r.first);
            }
            EXPECT_EQ(next, total);
            EXPECT_LE(largest - smallest, 1u);
        }
    EXPECT_THROW(shareRange(5, 2, 2), std::invalid_argument);
}

}  // namespace
}  // namespace partita
