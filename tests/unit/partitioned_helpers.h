// What the tests of the partitioned methods (`partitioned`, `guided`) share: tiny renders of the
// shipped scenes, the partitions a pre-pass makes, per-partition BDPT references (the layers of
// the types a partition holds, summed), and the convergence check of each partition's image and
// the combined one against them, per block over independent seeds with tolerances from their
// spread (statistics.h).
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "camera.h"
#include "film.h"
#include "gltf/gltf_loader.h"
#include "partition/partition.h"
#include "partition/pipeline_settings.h"
#include "partition/prepass.h"
#include "render_helpers.h"
#include "renderer.h"
#include "statistics.h"
#include "thread_pool.h"

namespace partita::partitioned_test {

constexpr int kWidth = 16, kHeight = 12, kBlocksX = 4, kBlocksY = 3, kMaxDepth = 8;

inline RenderScene loadScene(const std::string& name) {
    return RenderScene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/" + name + "/" + name + ".gltf"));
}

inline RenderSettings tinySettings(double budget, uint64_t seed, BudgetKind kind) {
    RenderSettings st;
    st.width = kWidth;
    st.height = kHeight;
    st.budget = budget;
    st.budgetKind = kind;
    st.seed = seed;
    st.maxDepth = kMaxDepth;
    st.previewIntervalSeconds = 0;
    st.everyTypeLayer = true;  // per-type comparisons: no type merged into "other"
    st.maxTypeLayers = 1024;
    return st;
}

/// The pre-pass and partitions of a scene, as `partitioned` makes them.
inline std::vector<Partition> partitionsOf(const RenderScene& scene, int k, uint64_t seed,
                                           uint64_t samples,
                                           PartitionShape shape = PartitionShape::Types,
                                           bool directApart = false) {
    Camera camera(resolveCamera(scene.data(), ""), kWidth, kHeight);
    RenderSettings st = tinySettings(1, seed, BudgetKind::MutationsPerPixel);
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    RenderContext ctx{scene, camera, st, pool, cancel, observer};
    std::string why;
    BootstrapSampler sampler(
        scene, camera, kMaxDepth, seed,
        choosePrepassEstimator(scene, PartitionPipelineSettings{}.prepass, why));
    return makePartitions(runPrepass(ctx, sampler, samples), k, kMaxBRelativeError, shape,
                          directApart);
}

/// Per block, the mean luminance of `image`.
inline std::vector<double> blocks(const Image& image) {
    std::vector<double> out(kBlocksX * kBlocksY, 0.0);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            out[size_t((y * kBlocksY / kHeight) * kBlocksX + x * kBlocksX / kWidth)] +=
                luminance(image.at(x, y));
    return out;
}

/// The reference of partition p: the BDPT image's layers of the types it holds, summed.
inline Image partitionReference(const LayeredImage& bdpt, const Partition& p) {
    Image sum(kWidth, kHeight);
    for (const ImageLayer& layer : bdpt.layers) {
        PathType t;
        EXPECT_TRUE(PathType::parse(layer.name, t))
            << "the reference dropped types: " << layer.name;
        if (!p.holds(t)) continue;
        for (size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += layer.image.rgb[i];
    }
    return sum;
}

/// The partitions a render made, from its statistics (partition_<g>_type): the direct light
/// (when apart), the patterns (one type or a class), then the complement of them all (when it
/// has one).
inline std::vector<Partition> partitionsOfRender(RenderResult& r) {
    std::vector<Partition> out;
    Partition complement;
    complement.label = kComplementLabel;
    complement.complement = true;
    int count = int(r.stats.values["partitions"]);
    const bool directApart = count > 0 && r.stats.labels["partition_0_type"] == kDirectLabel;
    complement.directApart = directApart;
    for (int g = 0; g < count; ++g) {
        std::string label = r.stats.labels["partition_" + std::to_string(g) + "_type"];
        if (label == kComplementLabel) {
            out.push_back(complement);
            continue;
        }
        Partition p;
        p.directApart = directApart;
        if (label == kDirectLabel) {
            p.label = label;
            p.direct = true;
            p.directApart = false;
            out.push_back(p);
            continue;
        }
        p.label = label;
        TypePattern pattern;
        EXPECT_TRUE(TypePattern::parse(label, pattern)) << label;
        p.patterns = {pattern};
        complement.patterns.push_back(pattern);
        out.push_back(p);
    }
    return out;
}

/// How many partitions (over all seeds) had chains and how many were estimated per pixel.
struct EstimatorCounts {
    int chains = 0, perPixel = 0;
    int direct = 0;  // the direct light's partitions (per pixel, counted in perPixel too)
};

/// Each partition's image (and the combined one) against the BDPT reference of its types, per
/// block, over independent seeds. The partitions are those of the render's own pre-pass, which
/// are the same for every seed only if the ranking is stable: the test compares by label.
/// `parameters`: the pipeline's, by name (estimators, allocation, partitions; others default).
inline EstimatorCounts expectPartitionsConverge(
    const std::string& algorithm, const std::string& sceneName, double mpp, double spp, int seeds,
    const std::map<std::string, std::string>& parameters = {}) {
    EstimatorCounts counts;
    RenderScene scene = loadScene(sceneName);
    std::map<std::string, std::vector<std::vector<double>>> mine, reference;
    for (int seed = 0; seed < seeds; ++seed) {
        RenderSettings st = tinySettings(mpp, 10 + uint64_t(seed), BudgetKind::MutationsPerPixel);
        st.parameters.set("k", 4);
        for (const auto& [name, value] : parameters) st.parameters.set(name, value);
        RenderResult r = test::renderWith(scene, algorithm, st);
        for (int g = 0; g < int(r.stats.values["partitions"]); ++g) {
            const std::string kind =
                r.stats.labels["partition_" + std::to_string(g) + "_estimator"];
            ++(kind == "per-pixel" ? counts.perPixel : counts.chains);
            counts.direct +=
                r.stats.labels["partition_" + std::to_string(g) + "_type"] == kDirectLabel;
        }
        LayeredImage bdpt =
            test::renderWith(scene, "bdpt",
                             tinySettings(spp, 600 + uint64_t(seed), BudgetKind::SamplesPerPixel))
                .image;
        mine["combined"].push_back(blocks(r.image.combined));
        reference["combined"].push_back(blocks(bdpt.combined));
        std::vector<Partition> partitions = partitionsOfRender(r);
        for (const Partition& p : partitions) {
            const Image* layer = r.image.layer(p.label);
            EXPECT_NE(layer, nullptr) << p.label;
            if (!layer) return counts;
            mine[p.label].push_back(blocks(*layer));
            reference[p.label].push_back(blocks(partitionReference(bdpt, p)));
        }
    }
    int comparisons = 0;
    for (const auto& [label, runs] : mine)
        if (int(runs.size()) == seeds) comparisons += kBlocksX * kBlocksY;
    for (const auto& [label, runs] : mine) {
        if (int(runs.size()) != seeds) continue;  // a partition not made by every seed
        for (size_t c = 0; c < size_t(kBlocksX * kBlocksY); ++c) {
            std::vector<double> a, b;
            for (const auto& v : runs) a.push_back(v[c]);
            for (const auto& v : reference[label]) b.push_back(v[c]);
            auto ma = test::meanAndError(a), mb = test::meanAndError(b);
            EXPECT_NEAR(ma.mean, mb.mean, test::twoSampleTolerance(ma, mb, comparisons))
                << sceneName << " " << label << " block " << c << ": " << algorithm << " "
                << ma.mean << " +- " << ma.standardError << ", bdpt " << mb.mean << " +- "
                << mb.standardError;
        }
    }
    EXPECT_GE(mine.size(), 4u);
    return counts;
}

}  // namespace partita::partitioned_test
