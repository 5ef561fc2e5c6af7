#include "in_process.h"

#include <atomic>
#include <cstring>

#include "gltf/gltf_loader.h"
#include "image_io.h"
#include "render_scene.h"
#include "renderer.h"
#include "thread_pool.h"

namespace partita::test {

LayeredImage renderInProcess(const fs::path& sceneFile, int width, int height, double spp,
                             uint64_t seed, const std::string& algorithm) {
    RenderScene scene(loadGltfFile(sceneFile));
    RenderSettings s;
    s.width = width;
    s.height = height;
    registerBuiltinAlgorithms();
    s.budgetKind = AlgorithmRegistry::instance().find(algorithm)->nativeBudget;
    s.budget = spp;
    s.seed = seed;
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    return runRender(scene, algorithm, s, pool, cancel, observer).image;
}

LayeredImage readExrBytes(const std::string& bytes, const std::string& name) {
    TempDir dir;
    writeFile(dir / name, bytes);
    return readExr(dir / name);
}

namespace {

Image rawImage(const pb::PreviewLayer& layer) {
    Image image(layer.width(), layer.height());
    if (layer.raw_rgb_f32().size() == image.rgb.size() * sizeof(float))
        std::memcpy(image.rgb.data(), layer.raw_rgb_f32().data(), layer.raw_rgb_f32().size());
    else
        image.rgb.clear();
    return image;
}

}  // namespace

LayeredImage frameImage(const pb::PreviewFrame& frame) {
    LayeredImage out;
    for (int i = 0; i < frame.layers_size(); ++i) {
        if (i == 0)
            out.combined = rawImage(frame.layers(0));
        else
            out.layers.push_back({frame.layers(i).name(), rawImage(frame.layers(i))});
    }
    return out;
}

namespace {

std::string compare(const std::string& name, const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        return name + ": size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
               " vs " + std::to_string(b.width) + "x" + std::to_string(b.height);
    if (a.rgb.size() != b.rgb.size()) return name + ": pixel data missing";
    for (size_t i = 0; i < a.rgb.size(); ++i)
        if (std::memcmp(&a.rgb[i], &b.rgb[i], sizeof(float)) != 0)
            return name + ": float " + std::to_string(i) + " differs (" + std::to_string(a.rgb[i]) +
                   " vs " + std::to_string(b.rgb[i]) + ")";
    return {};
}

}  // namespace

std::string compareImages(const LayeredImage& a, const LayeredImage& b) {
    if (std::string d = compare("combined", a.combined, b.combined); !d.empty()) return d;
    if (a.layers.size() != b.layers.size())
        return std::to_string(a.layers.size()) + " layers vs " + std::to_string(b.layers.size());
    for (size_t i = 0; i < a.layers.size(); ++i) {
        if (a.layers[i].name != b.layers[i].name)
            return "layer " + std::to_string(i) + " is '" + a.layers[i].name + "' vs '" +
                   b.layers[i].name + "'";
        if (std::string d = compare(a.layers[i].name, a.layers[i].image, b.layers[i].image);
            !d.empty())
            return d;
    }
    return {};
}

}  // namespace partita::test
