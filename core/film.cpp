// Film storage: a grid of kTileSize x kTileSize tiles. Every tile owns its combined RGB sums and
// a short vector of per-type buffers, created the first time a path of that type lands in the
// tile. Edge tiles are allocated full size so that the hot path indexes without clipping.
//
// Determinism: nothing in resolve/merge/typeCount depends on the order in which types were
// first seen in a tile (that order depends on thread scheduling). Type totals are summed over
// tiles in tile order and over pixels in pixel order, in double; the "other" layer adds its
// types in PathType order. What remains order dependent is only the float sum inside one pixel
// of one buffer, i.e. the order in which the caller added samples to that pixel.
#include "film.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>
#include <string>

namespace partita {

namespace {

constexpr int kTilePixels = Film::kTileSize * Film::kTileSize;
using TilePixels = std::array<Rgb, kTilePixels>;

int tileIndex(int x, int y) {
    return (y % Film::kTileSize) * Film::kTileSize + (x % Film::kTileSize);
}

}  // namespace

// Aligned so that two tiles written by different threads never share a cache line.
struct alignas(64) Film::Tile {
    struct TypeBuffer {
        PathType type;
        std::unique_ptr<TilePixels> pixels;
    };

    TilePixels combined{};
    std::vector<TypeBuffer> types;
    // Cache: per number of scattering vertices, the index into `types` of the last type used
    // with that count. A path reports types of increasing length, so a single "last used" entry
    // would miss every other sample; keyed by length it hits unless two types of equal length
    // (differing only in which vertices are specular) alternate.
    std::array<uint32_t, PathType::kMaxScatteringVertices + 1> lastByLength{};

    TilePixels& bufferFor(PathType type) {
        uint32_t& last = lastByLength[size_t(type.scatteringVertices())];
        if (last < types.size() && types[last].type == type) return *types[last].pixels;
        for (size_t i = 0; i < types.size(); ++i) {
            if (types[i].type == type) {
                last = uint32_t(i);
                return *types[i].pixels;
            }
        }
        types.push_back({type, std::make_unique<TilePixels>()});
        last = uint32_t(types.size() - 1);
        return *types.back().pixels;
    }

    void clear() {
        combined.fill(Rgb(0.0f));
        types.clear();
        lastByLength.fill(0);
    }
};

Film::Film(int width, int height) : width_(width), height_(height) {
    if (width < 0 || height < 0)
        throw std::invalid_argument("Film: negative size " + std::to_string(width) + "x" +
                                    std::to_string(height));
    tiles_.resize(size_t(tilesX()) * tilesY());
    for (auto& t : tiles_) t = std::make_unique<Tile>();
}

Film::~Film() = default;

Film::Film(Film&& o) noexcept
    : width_(o.width_),
      height_(o.height_),
      tiles_(std::move(o.tiles_)),
      dropped_(o.dropped_.load()) {
    o.width_ = o.height_ = 0;
    o.tiles_.clear();
    o.dropped_ = 0;
}

Film& Film::operator=(Film&& o) noexcept {
    if (this != &o) {
        width_ = o.width_;
        height_ = o.height_;
        tiles_ = std::move(o.tiles_);
        dropped_ = o.dropped_.load();
        o.width_ = o.height_ = 0;
        o.tiles_.clear();
        o.dropped_ = 0;
    }
    return *this;
}

Film::Tile& Film::tileFor(int x, int y) {
    return *tiles_[size_t(y / kTileSize) * size_t(tilesX()) + size_t(x / kTileSize)];
}

void Film::addSample(int x, int y, PathType type, Rgb value) {
    // Unsigned compares catch negative coordinates too; a sample outside the film is a caller
    // bug, ignored rather than written out of bounds.
    if (unsigned(x) >= unsigned(width_) || unsigned(y) >= unsigned(height_)) return;
    Pixel(*this, tileFor(x, y), tileIndex(x, y)).add(type, value);
}

Film::Pixel Film::pixel(int x, int y) {
    if (unsigned(x) >= unsigned(width_) || unsigned(y) >= unsigned(height_))
        throw std::out_of_range("Film::pixel: (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") is outside the film");
    return Pixel(*this, tileFor(x, y), tileIndex(x, y));
}

void Film::Pixel::add(PathType type, Rgb value) {
    if (!isFinite(value)) {
        film_->dropped_.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    // A black sample changes no sum; skipping it also keeps zero-contribution types from
    // allocating buffers.
    if (isBlack(value)) return;
    tile_->combined[index_] += value;
    tile_->bufferFor(type)[index_] += value;
}

void Film::merge(const Film& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw std::invalid_argument("Film::merge: size mismatch (" + std::to_string(width_) + "x" +
                                    std::to_string(height_) + " vs " +
                                    std::to_string(other.width_) + "x" +
                                    std::to_string(other.height_) + ")");
    if (&other == this) {
        // Doubling in place: adding a film to itself.
        for (auto& tile : tiles_) {
            for (auto& p : tile->combined) p += p;
            for (auto& t : tile->types)
                for (auto& p : *t.pixels) p += p;
        }
        dropped_ += dropped_.load();
        return;
    }
    for (size_t ti = 0; ti < tiles_.size(); ++ti) {
        Tile& dst = *tiles_[ti];
        const Tile& src = *other.tiles_[ti];
        for (int i = 0; i < kTilePixels; ++i) dst.combined[i] += src.combined[i];
        for (const auto& t : src.types) {
            TilePixels& d = dst.bufferFor(t.type);
            for (int i = 0; i < kTilePixels; ++i) d[i] += (*t.pixels)[i];
        }
    }
    dropped_.fetch_add(other.dropped_.load(), std::memory_order_relaxed);
}

void Film::clear() {
    for (auto& t : tiles_) t->clear();
    dropped_ = 0;
}

Image Film::resolveCombined(float scale) const {
    Image img(width_, height_);
    const int tx = tilesX();
    for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
            const Tile& tile = *tiles_[size_t(y / kTileSize) * tx + x / kTileSize];
            img.set(x, y, tile.combined[tileIndex(x, y)] * scale);
        }
    }
    return img;
}

LayeredImage Film::resolve(float scale, int maxTypeLayers) const {
    LayeredImage out;
    out.combined = resolveCombined(scale);

    // Total luminance per type. std::map keeps the types in PathType order, and the sums run
    // over tiles and pixels in a fixed order, so the totals do not depend on insertion order.
    std::map<PathType, double> totals;
    const int tx = tilesX();
    for (size_t ti = 0; ti < tiles_.size(); ++ti) {
        const Tile& tile = *tiles_[ti];
        const int x0 = int(ti % tx) * kTileSize, y0 = int(ti / tx) * kTileSize;
        const int w = std::min(kTileSize, width_ - x0), h = std::min(kTileSize, height_ - y0);
        for (const auto& t : tile.types) {
            double sum = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) sum += luminance((*t.pixels)[y * kTileSize + x]);
            totals[t.type] += sum;
        }
    }

    // Rank: largest total first, ties by PathType order (stable sort over the ordered map).
    std::vector<std::pair<PathType, double>> ranked(totals.begin(), totals.end());
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    const size_t keep = std::min(ranked.size(), size_t(std::max(0, maxTypeLayers)));
    const bool hasOther = ranked.size() > keep;

    // Layer index per type: 0..keep-1 for the kept types, `keep` for "other".
    std::map<PathType, size_t> layerOf;
    for (size_t i = 0; i < ranked.size(); ++i) layerOf[ranked[i].first] = std::min(i, keep);

    // Unscaled sums, scaled at the end (like the combined image).
    std::vector<Image> layers(keep + (hasOther ? 1 : 0), Image(width_, height_));
    std::vector<const Tile::TypeBuffer*> sorted;
    for (size_t ti = 0; ti < tiles_.size(); ++ti) {
        const Tile& tile = *tiles_[ti];
        const int x0 = int(ti % tx) * kTileSize, y0 = int(ti / tx) * kTileSize;
        const int w = std::min(kTileSize, width_ - x0), h = std::min(kTileSize, height_ - y0);
        // Visit the tile's types in PathType order so that "other" sums in a fixed order.
        sorted.clear();
        for (const auto& t : tile.types) sorted.push_back(&t);
        std::sort(sorted.begin(), sorted.end(),
                  [](const auto* a, const auto* b) { return a->type < b->type; });
        for (const auto* t : sorted) {
            Image& dst = layers[layerOf.at(t->type)];
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    dst.add(x0 + x, y0 + y, (*t->pixels)[y * kTileSize + x]);
        }
    }
    for (auto& img : layers)
        for (float& v : img.rgb) v *= scale;

    out.layers.reserve(layers.size());
    for (size_t i = 0; i < keep; ++i)
        out.layers.push_back({ranked[i].first.toString(), std::move(layers[i])});
    if (hasOther) out.layers.push_back({kOtherLayer, std::move(layers[keep])});
    return out;
}

size_t Film::typeCount() const {
    std::vector<PathType> all;
    for (const auto& tile : tiles_)
        for (const auto& t : tile->types) all.push_back(t.type);
    std::sort(all.begin(), all.end());
    return size_t(std::unique(all.begin(), all.end()) - all.begin());
}

uint64_t Film::droppedSamples() const {
    return dropped_.load(std::memory_order_relaxed);
}

}  // namespace partita
