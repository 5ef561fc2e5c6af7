#include "reference.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "eval/reference_key.h"
#include "eval_render.h"
#include "image_io.h"
#include "image_metrics.h"
#include "render_scene.h"
#include "renderer.h"
#include "thread_pool.h"

namespace partita::eval {

namespace fs = std::filesystem;

namespace {

using Metadata = std::map<std::string, std::string>;

std::string numberText(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// Every option, the key and its text, and the error per layer, as EXR string attributes.
Metadata referenceMetadata(const ReferenceOptions& o, const RenderSettings& total,
                           const std::string& key, const std::string& keyText,
                           const std::vector<LayerError>& errors, const TimedRender halves[2]) {
    Metadata m = describeRender(o.render.algorithm, total, {});
    m["partita:max_type_layers"] =
        std::to_string(total.maxTypeLayers);  // "partita:layers" is the order
    m["partita:reference:scene"] = o.scene;
    m["partita:reference:key"] = key;
    m["partita:reference:key_text"] = keyText;
    m["partita:reference:format"] = std::to_string(kReferenceFormat);
    for (int h = 0; h < 2; ++h) {
        std::string prefix = "partita:reference:half" + std::to_string(h) + ":";
        m[prefix + "seed"] = std::to_string(referenceHalfSeed(total.seed, h));
        m[prefix + "budget"] = numberText(total.budget / 2);
        m[prefix + "wall_seconds"] = numberText(halves[h].wallSeconds);
        for (const auto& [k, v] : halves[h].result.stats.values)
            m[prefix + "stat:" + k] = numberText(v);
    }
    for (const auto& e : errors) {
        m["partita:reference:rmse:" + e.layer] = numberText(e.rmse);
        m["partita:reference:relmse:" + e.layer] = numberText(e.relMse);
    }
    return m;
}

constexpr size_t kPrintedLayers = 16;  // the rest is in the file's attributes and the JSON

/// The reference's own error per layer, with the layer's mean value for scale.
void printErrors(const LayeredImage& image, const std::vector<LayerError>& errors) {
    std::printf("  %-24s %14s %14s %14s\n", "layer", "mean value", "own RMSE", "own relMSE");
    for (size_t i = 0; i < errors.size(); ++i) {
        const LayerError& e = errors[i];
        if (i == kPrintedLayers) {
            std::printf("  ... and %zu more layers\n", errors.size() - i);
            break;
        }
        const Image* layer = e.layer == kCombinedLayerName ? &image.combined : image.layer(e.layer);
        Rgb mean = layer ? layer->mean() : Rgb{};
        std::printf("  %-24s %14.6g %14.6g %14.6g\n", e.layer.c_str(),
                    (mean.x + mean.y + mean.z) / 3.0, e.rmse, e.relMse);
    }
}

/// The error figures back from a cached file's attributes, "combined" first.
std::vector<LayerError> errorsFromMetadata(const LayeredImage& image, const Metadata& m) {
    std::vector<LayerError> out;
    auto add = [&](const std::string& name) {
        auto r = m.find("partita:reference:rmse:" + name);
        auto q = m.find("partita:reference:relmse:" + name);
        if (r != m.end() && q != m.end())
            out.push_back({name, std::atof(r->second.c_str()), std::atof(q->second.c_str())});
    };
    add(kCombinedLayerName);
    for (const auto& layer : image.layers) add(layer.name);
    return out;
}

RenderSettings checkedSettings(ReferenceOptions& o) {
    if (std::string err = finalizeRenderOptions(o.render); !err.empty())
        throw std::invalid_argument(err);
    RenderSettings s = o.render.settings;
    if (s.budgetKind == BudgetKind::Seconds)
        throw std::invalid_argument(
            "a reference needs --spp or --mpp: a time budget is not reproducible, so it could "
            "not be cached");
    if (s.budget < 2)
        throw std::invalid_argument("a reference needs a budget of at least 2 (two halves)");
    s.budget = 2 * std::ceil(s.budget / 2);  // two equal halves; an odd budget rounds up
    return s;
}

nlohmann::json summary(const std::string& path, const std::string& key, bool cached, double seconds,
                       const std::vector<LayerError>& errors) {
    nlohmann::json layers = nlohmann::json::array();
    for (const auto& e : errors)
        layers.push_back({{"layer", e.layer}, {"rmse", e.rmse}, {"relmse", e.relMse}});
    return {{"reference", path},
            {"key", key},
            {"cached", cached},
            {"seconds", seconds},
            {"own_error", layers}};
}

void copyTo(const fs::path& from, const std::string& out) {
    if (out.empty()) return;
    std::error_code ec;
    if (fs::exists(out) && fs::equivalent(from, out, ec)) return;
    fs::copy_file(from, out, fs::copy_options::overwrite_existing);
}

}  // namespace

std::string defaultReferenceCache() {
    if (const char* env = std::getenv("PARTITA_REFERENCE_CACHE"); env && *env) return env;
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return "references";
    return (exe.parent_path().parent_path() / "references").string();
}

nlohmann::json runReference(ReferenceOptions o) {
    RenderSettings total = checkedSettings(o);
    if (o.noCache && o.out.empty())
        throw std::invalid_argument("--no-cache needs --out (the reference must go somewhere)");
    std::vector<SceneFile> files = sceneFiles(o.scene);
    std::string keyText = referenceKeyText(files, o.render.algorithm, total);
    std::string key = referenceKey(files, o.render.algorithm, total);
    fs::path cacheDir = o.cacheDir.empty() ? defaultReferenceCache() : o.cacheDir;
    fs::path cached = cacheDir / (fs::path(o.scene).stem().string() + "-" + key + ".exr");

    if (!o.noCache && !o.force && fs::exists(cached)) {
        Metadata m;
        LayeredImage image = readExr(cached, &m);
        copyTo(cached, o.out);
        auto errors = errorsFromMetadata(image, m);
        std::printf("reference %s (cached; key %s)%s%s\n", cached.string().c_str(), key.c_str(),
                    o.out.empty() ? "" : ", copied to ", o.out.c_str());
        printErrors(image, errors);
        return summary(cached.string(), key, true, 0, errors);
    }

    auto scene = loadRenderScene(o.scene, o.render.settings.environment);
    ThreadPool pool(o.render.threads);
    TimedRender halves[2];
    for (int h = 0; h < 2; ++h) {
        RenderSettings half = total;
        half.budget = total.budget / 2;
        half.seed = referenceHalfSeed(total.seed, h);
        halves[h] = renderTimed(*scene, o.render.algorithm, half, pool, o.quiet,
                                "half " + std::to_string(h + 1) + "/2");
    }
    // Scenes with more types than --layers keep different ones per half (the rest in "other").
    foldUnsharedLayers(halves[0].result.image, halves[1].result.image);
    auto errors = halfSplitError(halves[0].result.image, halves[1].result.image);
    LayeredImage image = meanOfTwo(std::move(halves[0].result.image), halves[1].result.image);
    halves[1].result.image = {};  // a layered image can be large: layers x width x height x 12 B
    Metadata meta = referenceMetadata(o, total, key, keyText, errors, halves);
    double seconds = halves[0].wallSeconds + halves[1].wallSeconds;
    fs::path written = o.noCache ? fs::path(o.out) : cached;
    if (!o.noCache) fs::create_directories(cacheDir);
    writeExr(written, image, meta);
    if (!o.noCache) copyTo(cached, o.out);
    std::printf("reference %s: %s, %s %dx%d, %s, %zu type layers, %.1f s (key %s)%s%s\n",
                written.string().c_str(), o.scene.c_str(), o.render.algorithm.c_str(), total.width,
                total.height, budgetText(total).c_str(), image.layers.size(), seconds, key.c_str(),
                o.noCache || o.out.empty() ? "" : ", copied to ", o.noCache ? "" : o.out.c_str());
    printErrors(image, errors);
    return summary(written.string(), key, false, seconds, errors);
}

}  // namespace partita::eval
