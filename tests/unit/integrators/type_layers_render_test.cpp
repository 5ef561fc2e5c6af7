// Bounded type layers in real renders (issue #24). bathroom produces thousands of path types,
// hundreds per tile; with L layers every algorithm's film holds at most L + 2 buffers per tile
// (the kept types, "other" and the combined sums), the partitions' chains' films none but the
// combined one, and their per-pixel film one a partition. The films are read from a one-shard
// render (shard/), whose film is the one-process film bit for bit (shards_test.cpp).
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
    // The partitions' chains keep their combined images only; the per-pixel partitions
    // (estimators=auto, the default) one film with a buffer per partition besides the combined
    // one: at most K + 3 (K, the direct light and the complement), whatever --layers says.
    RenderSettings chains = settingsFor("partitioned", 32);
    chains.parameters.set("estimators", std::string("chains"));
    EXPECT_EQ(buffersPerTile("partitioned", chains), 1u);
    for (int layers : {0, 32}) {
        RenderSettings chosen = settingsFor("partitioned", layers);
        chosen.parameters.set("k", 4);
        const size_t most = buffersPerTile("partitioned", chosen);
        EXPECT_LE(most, 4u + 3u) << layers << " layers";
        EXPECT_GT(most, 1u) << layers << " layers: some partitions per pixel";
    }
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
