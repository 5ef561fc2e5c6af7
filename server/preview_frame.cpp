#include "preview_frame.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstring>

#include "image_io.h"

namespace partita::server {

PreviewFrameData::PreviewFrameData(uint64_t sequence, bool final, LayeredImage image)
    : sequence_(sequence),
      final_(final),
      image_(std::make_shared<const LayeredImage>(std::move(image))) {}

PreviewFrameData::PreviewFrameData(uint64_t sequence, std::filesystem::path resultExr)
    : sequence_(sequence), final_(true), exr_(std::move(resultExr)) {}

std::shared_ptr<const LayeredImage> PreviewFrameData::image() const {
    if (image_) return image_;
    return std::make_shared<const LayeredImage>(readExr(exr_));
}

namespace {

std::string rawBytes(const Image& image) {
    static_assert(sizeof(float) == 4);
    // The wire format is little-endian float32; so is every platform partitad builds on.
    std::string bytes(image.rgb.size() * sizeof(float), '\0');
    if (!bytes.empty()) std::memcpy(bytes.data(), image.rgb.data(), bytes.size());
    return bytes;
}

}  // namespace

pb::PreviewFrame PreviewFrameData::encode(bool raw) const {
    std::shared_ptr<const LayeredImage> img = image();
    std::vector<std::string> pngs;
    {
        std::lock_guard lock(mutex_);
        if (pngs_) pngs = *pngs_;
    }
    if (pngs.empty()) {
        // Encoding outside the lock: two watchers racing at most encode twice, never block.
        auto start = std::chrono::steady_clock::now();
        const float exposure = autoExposure(img->combined);
        auto png = [exposure](const Image& image) {
            std::vector<uint8_t> bytes = encodePng(image, exposure, PngOptions{.fast = true});
            return std::string(bytes.begin(), bytes.end());
        };
        pngs.reserve(img->layers.size() + 1);
        pngs.push_back(png(img->combined));
        for (const auto& layer : img->layers) pngs.push_back(png(layer.image));
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        encodeSeconds_.store(seconds);
        spdlog::debug("preview frame {}: {} PNGs of {}x{} in {:.1f} ms", sequence_, pngs.size(),
                      img->combined.width, img->combined.height, 1000 * seconds);
        if (image_) {
            std::lock_guard lock(mutex_);
            if (!pngs_) pngs_ = pngs;
        }
    }
    pb::PreviewFrame frame;
    frame.set_sequence(sequence_);
    frame.set_final(final_);
    auto addLayer = [&](const std::string& name, const Image& image, std::string& png) {
        pb::PreviewLayer* layer = frame.add_layers();
        layer->set_name(name);
        layer->set_width(image.width);
        layer->set_height(image.height);
        layer->set_png(std::move(png));
        if (raw) layer->set_raw_rgb_f32(rawBytes(image));
    };
    addLayer("combined", img->combined, pngs[0]);
    for (size_t i = 0; i < img->layers.size(); ++i)
        addLayer(img->layers[i].name, img->layers[i].image, pngs[i + 1]);
    return frame;
}

}  // namespace partita::server
