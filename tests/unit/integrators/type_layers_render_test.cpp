// Bounded type layers in real renders (issue #24). bathroom produces thousands of path types,
// hundreds per tile; with L layers every algorithm's film holds at most L + 2 buffers per tile
// (the kept types, "other" and the combined sums), and the partitions' films none but the
// combined one. The films are read from a one-shard render (shard/), whose film is the
// one-process film bit for bit (shards_test.cpp).
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include "gltf/gltf_loader.h"
#include "render_scene.h"
#include "shard/sharded_render.h"
#include "thread_pool.h"

namespace partita {
namespace {

const RenderScene& bathroom() {
    static const RenderScene scene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/bathroom/bathroom.gltf"));
    return scene;
}

RenderSettings settingsFor(const std::string& algorithm, int layers) {
    RenderSettings s;
    s.width = 64;
    s.height = 48;
    s.seed = 3;
    s.previewIntervalSeconds = 0;
    s.maxTypeLayers = layers;
    const bool chains = algorithm != "pt" && algorithm != "bdpt";
    s.budgetKind = chains ? BudgetKind::MutationsPerPixel : BudgetKind::SamplesPerPixel;
    s.budget = 2;
    if (chains) s.parameters.set("bootstrap", 4000);
    return s;
}

/// The film of a one-shard render of bathroom.
size_t buffersPerTile(const std::string& algorithm, const RenderSettings& settings) {
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    ShardEnvironment env{bathroom(), pool, cancel, observer};
    const ShardPlan plan = planShardedRender(env, algorithm, settings, 1, "bathroom", 1);
    const ShardResult result = renderPlannedShard(env, plan, 0);
    size_t most = 0;
    for (const Film& film : result.work.films) most = std::max(most, film.maxBuffersPerTile());
    return most;
}

TEST(BoundedTypeLayers, BathroomFilmsHoldAtMostTheLayersPlusTwoBuffersPerTile) {
    for (const char* algorithm : {"pt", "bdpt", "mlt"}) {
        for (int layers : {0, 8, 32}) {
            SCOPED_TRACE(testing::Message() << algorithm << ", " << layers << " layers");
            const size_t most = buffersPerTile(algorithm, settingsFor(algorithm, layers));
            EXPECT_LE(most, size_t(layers == 0 ? 1 : layers + 2));
            EXPECT_GE(most, 1u);
        }
    }
    // The partitions keep their combined images only.
    EXPECT_EQ(buffersPerTile("partitioned", settingsFor("partitioned", 32)), 1u);
}

TEST(BoundedTypeLayers, BathroomHasFarMoreTypesPerTileThanLayers) {
    // Without the bound the same render holds hundreds of buffers in some tile: the test above
    // can fail.
    RenderSettings every = settingsFor("pt", 32);
    every.everyTypeLayer = true;
    EXPECT_GT(buffersPerTile("pt", every), 100u);
}

}  // namespace
}  // namespace partita
