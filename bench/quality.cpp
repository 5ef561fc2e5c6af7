#include "quality.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>

#include "algorithm.h"
#include "eval/peak_rss.h"
#include "eval/reference_key.h"
#include "eval_render.h"
#include "film.h"
#include "image_io.h"
#include "partition/partition.h"
#include "quality_run.h"
#include "render_scene.h"
#include "thread_pool.h"
#ifdef PARTITA_EVAL_SERVICE
#include "job_memory.h"
#endif

namespace partita::eval {

namespace {

using Metadata = std::map<std::string, std::string>;

struct Reference {
    LayeredImage image;
    Metadata metadata;
    ReferenceErrors errors;
    std::vector<std::string> layerOrder;  // "combined", then the reference's layers
};

Reference loadReference(const std::string& path) {
    Reference r;
    r.image = readExr(path, &r.metadata);
    r.layerOrder.push_back(kCombinedLayerName);
    for (const auto& l : r.image.layers) r.layerOrder.push_back(l.name);
    for (const auto& name : r.layerOrder) {
        auto rmse = r.metadata.find("partita:reference:rmse:" + name);
        auto rel = r.metadata.find("partita:reference:relmse:" + name);
        if (rmse != r.metadata.end() && rel != r.metadata.end())
            r.errors[name] = {name, std::atof(rmse->second.c_str()),
                              std::atof(rel->second.c_str())};
    }
    return r;
}

/// Every algorithm resolved (an unknown name is the registry's one-line error) before anything
/// renders. Each takes the given parameters it declares (--k for partitioned and guided, not
/// for mlt); a parameter no algorithm of the list declares is an error.
std::vector<RenderOptions> resolveAlgorithms(const QualityOptions& o) {
    if (o.algorithms.empty()) throw std::invalid_argument("--algorithms names none");
    registerBuiltinAlgorithms();
    for (const auto& [name, value] : o.render.given) {
        bool declared = findParameter(sharedParameters().specs(), name);
        for (const auto& a : o.algorithms)
            if (const auto* entry = AlgorithmRegistry::instance().find(a))
                declared = declared || findParameter(entry->parameters, name);
        if (!declared)
            throw std::invalid_argument("parameter '" + name + "' is not one of " +
                                        "the algorithms' parameters");
    }
    std::vector<RenderOptions> out;
    for (const auto& name : o.algorithms) {
        RenderOptions r = o.render;
        r.algorithm = name;
        if (const auto* entry = AlgorithmRegistry::instance().find(name))
            for (const auto& [param, value] : o.render.given)
                if (!findParameter(sharedParameters().specs(), param) &&
                    !findParameter(entry->parameters, param))
                    r.given.erase(param);
        if (std::string err = finalizeRenderOptions(r); !err.empty())
            throw std::invalid_argument(err);
        out.push_back(r);
    }
    return out;
}

/// The reference's size, or a clear error when the one asked for differs.
void matchReferenceSize(QualityOptions& o, const Reference& ref) {
    RenderSettings& s = o.render.settings;
    int w = ref.image.combined.width, h = ref.image.combined.height;
    if (o.sizeGiven && (s.width != w || s.height != h))
        throw std::invalid_argument("reference " + o.reference + " is " + std::to_string(w) + "x" +
                                    std::to_string(h) + ", but the renders would be " +
                                    std::to_string(s.width) + "x" + std::to_string(s.height) +
                                    " (leave out --width/--height to use the reference's size)");
    s.width = w;
    s.height = h;
}

/// Warnings, not errors: a reference of another scene, camera or depth still compares, but the
/// difference is then bias, not noise.
void warnOnMismatch(const QualityOptions& o, const Reference& ref) {
    const Metadata& m = ref.metadata;
    const RenderSettings& s = o.render.settings;
    auto differs = [&](const char* key, const std::string& mine) {
        auto it = m.find(key);
        return it != m.end() && it->second != mine;
    };
    if (differs("partita:max_depth", std::to_string(s.maxDepth)))
        std::fprintf(stderr, "warning: the reference has max depth %s, these renders %d\n",
                     m.at("partita:max_depth").c_str(), s.maxDepth);
    if (differs("partita:camera", s.cameraName))
        std::fprintf(stderr, "warning: the reference is of camera '%s', these renders of '%s'\n",
                     m.at("partita:camera").c_str(), s.cameraName.c_str());
    auto keyText = m.find("partita:reference:key_text");
    if (keyText == m.end()) return;
    for (const auto& f : sceneFiles(o.scene)) {
        std::string line = "file " + f.name + " " + std::to_string(f.size) + " " + f.hash + "\n";
        if (keyText->second.find(line) == std::string::npos)
            std::fprintf(stderr, "warning: %s of %s differs from the reference's scene\n",
                         f.name.c_str(), o.scene.c_str());
    }
}

SeedRun measure(const TimedRender& r, const Reference& ref, const RenderSettings& s) {
    SeedRun run;
    run.seed = s.seed;
    run.errors = compareLayers(r.result.image, ref.image);
    run.wallSeconds = r.wallSeconds;
    const auto& v = r.result.stats.values;
    if (auto it = v.find("spp"); it != v.end()) {
        run.unitsPerPixel = it->second;
        run.unit = "samples";
    } else if (auto m = v.find("mpp"); m != v.end()) {
        run.unitsPerPixel = m->second;
        run.unit = "mutations";
    } else if (s.budgetKind != BudgetKind::Seconds) {  // an algorithm that does not say
        run.unitsPerPixel = s.budget;
        run.unit = s.budgetKind == BudgetKind::SamplesPerPixel ? "samples" : "mutations";
    }
    run.stats = v;
    run.labels = r.result.stats.labels;
    run.acceptance = overallAcceptance(run.stats);
    // Computed on the fly (no image is allocated), so it does not add to the measured peak.
    run.partitions = partitionErrors(r.result.image, partitionLabels(run.labels), ref.image);
    return run;
}

/// The daemon's estimate of what one job of these settings adds (server/job_memory.h), for a
/// comparison with the measured peak; the scene's bytes are its file and resources.
void addMemoryEstimate(AlgorithmRun& run, const QualityOptions& o, const ThreadPool& pool) {
#ifdef PARTITA_EVAL_SERVICE
    uint64_t sceneBytes = 0;
    for (const auto& f : sceneFiles(o.scene)) sceneBytes += f.size;
    auto e =
        server::estimateJobMemory(run.algorithm, run.settings, sceneBytes, int(pool.threadCount()));
    run.estimateMb = double(e.bytes) / double(1 << 20);
    run.estimateBreakdown = e.breakdown;
#else
    (void)run;
    (void)o;
    (void)pool;
#endif
}

/// The bytes of an image's pixels, in MiB.
double imageMb(const LayeredImage& image) {
    double bytes = double(image.combined.rgb.size()) * sizeof(float);
    for (const auto& l : image.layers) bytes += double(l.image.rgb.size()) * sizeof(float);
    return bytes / double(1 << 20);
}

/// The algorithms whose renders have one layer per partition.
bool hasPartitionLayers(const std::string& algorithm) {
    return algorithm == "partitioned" || algorithm == "guided";
}

/// `kept` receives the renders' images (for decomposeIntoPartitions) when it is not null.
AlgorithmRun runAlgorithm(const RenderOptions& r, const QualityOptions& o, const Reference& ref,
                          const RenderScene& scene, ThreadPool& pool,
                          std::vector<LayeredImage>* kept) {
    AlgorithmRun run;
    run.algorithm = r.algorithm;
    run.settings = r.settings;
    run.peakPerAlgorithm = resetPeakRss();
    double before = currentRssMb();
    // The kept images are resident while the later seeds render: the peak is measured per seed
    // (reset before each) and what was kept before that seed is taken off it.
    double keptMb = 0;
    for (int k = 0; k < o.seeds; ++k) {
        if (k > 0 && run.peakPerAlgorithm) resetPeakRss();
        RenderSettings s = r.settings;
        s.seed = r.settings.seed + uint64_t(k);
        std::string label = r.algorithm + " seed " + std::to_string(s.seed);
        TimedRender t = renderTimed(scene, r.algorithm, s, pool, o.quiet, label);
        run.runs.push_back(measure(t, ref, s));
        run.peakRssMb = std::max(run.peakRssMb, peakRssMb() - keptMb);
        if (kept) {
            keptMb += imageMb(t.result.image);
            kept->push_back(std::move(t.result.image));
        }
    }
    run.rssIncreaseMb = std::max(0.0, run.peakRssMb - before);
    addMemoryEstimate(run, o, pool);
    return run;
}

/// The error of a render without partition layers (mlt, pt) on the partitions of `partitioned`'s
/// render of the same seed: its layers of the partitions' types (summed for a class or the direct
/// light, eval/partition_error.h partitionLayer), and as the complement its combined image minus
/// those. A seed is left out when its render may hold part of a partition in "other" (it cannot
/// be told apart there); a type it lacks with no "other" is black.
void decomposeIntoPartitions(AlgorithmRun& run, const std::vector<LayeredImage>& images,
                             const AlgorithmRun& partitioned, const Reference& ref) {
    run.partitionsOf = partitioned.algorithm;
    for (size_t k = 0; k < run.runs.size() && k < images.size(); ++k) {
        SeedRun& seed = run.runs[k];
        const LayeredImage& image = images[k];
        const SeedRun* twin = nullptr;
        for (const auto& p : partitioned.runs)
            if (p.seed == seed.seed && !p.partitions.empty()) twin = &p;
        if (!twin) continue;
        std::vector<std::string> names;
        bool directApart = false;
        for (const auto& e : twin->partitions) {
            names.push_back(e.layer);
            directApart = directApart || e.layer == kDirectLabel;
        }
        LayeredImage d;
        d.combined = image.combined;
        Image complement = image.combined;
        bool separable = true;
        for (const auto& name : names) {
            if (name == kComplementLabel) continue;
            bool complete = true;
            Image layer = partitionLayer(image, name, directApart, complete);
            separable = separable && (complete || !image.layer(Film::kOtherLayer));
            for (size_t i = 0; i < complement.rgb.size(); ++i) complement.rgb[i] -= layer.rgb[i];
            d.layers.push_back({name, std::move(layer)});
        }
        if (!separable) continue;
        d.layers.push_back({kComplementLabel, std::move(complement)});
        seed.partitions = partitionErrors(d, names, ref.image);
    }
}

/// The scene, the reference and its own error: a measured RMSE^2 is about the render's error^2
/// plus the reference's own error^2.
void printHeader(const QualityOptions& o, const Reference& ref) {
    std::printf("scene %s %dx%d, %s%s\n", o.scene.c_str(), o.render.settings.width,
                o.render.settings.height, o.equalTime ? "equal time, " : "",
                ("max depth " + std::to_string(o.render.settings.maxDepth)).c_str());
    auto own = ref.errors.find(kCombinedLayerName);
    if (own == ref.errors.end()) {
        std::printf("reference %s (its own error is unknown: not made by partita-eval)\n",
                    o.reference.c_str());
        return;
    }
    std::printf(
        "reference %s, own RMSE %.4g, relMSE %.4g (measured RMSE^2 ~ render's^2 + "
        "reference's^2)\n",
        o.reference.c_str(), own->second.rmse, own->second.relMse);
}

nlohmann::json report(const QualityOptions& o, const Reference& ref,
                      const std::vector<AlgorithmRun>& runs) {
    nlohmann::json j;
    j["scene"] = o.scene;
    j["width"] = o.render.settings.width;
    j["height"] = o.render.settings.height;
    j["reference"] = o.reference;
    auto own = ref.errors.find(kCombinedLayerName);
    j["reference_rmse"] =
        own == ref.errors.end() ? nlohmann::json() : nlohmann::json(own->second.rmse);
    j["reference_relmse"] =
        own == ref.errors.end() ? nlohmann::json() : nlohmann::json(own->second.relMse);
    j["equal_time"] = o.equalTime;
    j["max_depth"] = o.render.settings.maxDepth;
    j["threads"] = o.render.threads;
    j["peak_rss_method"] =
        "VmHWM of the process, reset (clear_refs) before each algorithm's renders; the scene "
        "and reference are resident throughout";
    j["relmse_definition"] = "mean over pixels and RGB channels of (x - r)^2 / (r^2 + 1e-2)";
    nlohmann::json results = nlohmann::json::array();
    for (const auto& r : runs)
        results.push_back(resultJson(r, runs.front(), ref.layerOrder, ref.errors));
    j["results"] = results;
    return j;
}

}  // namespace

nlohmann::json runQuality(QualityOptions o) {
    if (o.seeds < 1) throw std::invalid_argument("--seeds must be at least 1");
    std::vector<RenderOptions> algorithms = resolveAlgorithms(o);
    Reference ref = loadReference(o.reference);
    matchReferenceSize(o, ref);
    for (auto& a : algorithms) {
        a.settings.width = o.render.settings.width;
        a.settings.height = o.render.settings.height;
    }
    warnOnMismatch(o, ref);
    auto scene = loadRenderScene(o.scene, o.render.settings.environment);
    ThreadPool pool(o.render.threads);
    std::vector<AlgorithmRun> runs;
    std::vector<std::vector<LayeredImage>> kept(algorithms.size());
    for (size_t i = 0; i < algorithms.size(); ++i) {
        if (o.equalTime && i > 0) {
            algorithms[i].settings.budgetKind = BudgetKind::Seconds;
            algorithms[i].settings.budget = meanWallSeconds(runs.front());
        }
        // The renders of an algorithm without partitions are kept until a partitioned one of
        // the same run has rendered, to be measured on its partitions too.
        bool keep =
            !hasPartitionLayers(algorithms[i].algorithm) &&
            std::any_of(algorithms.begin() + long(i) + 1, algorithms.end(),
                        [](const RenderOptions& a) { return hasPartitionLayers(a.algorithm); });
        kept[i].clear();
        runs.push_back(
            runAlgorithm(algorithms[i], o, ref, *scene, pool, keep ? &kept[i] : nullptr));
    }
    for (const auto& p : runs) {
        if (!hasPartitionLayers(p.algorithm)) continue;
        for (size_t i = 0; i < runs.size(); ++i)
            if (!kept[i].empty()) decomposeIntoPartitions(runs[i], kept[i], p, ref);
        break;
    }
    kept.clear();
    printHeader(o, ref);
    printQualityTables(runs, ref.layerOrder, ref.errors, size_t(o.tableLayers));
    return report(o, ref, runs);
}

}  // namespace partita::eval
