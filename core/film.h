// The film: accumulates path contributions into a combined image and one image per path type.
//
// Storage is tiled and sparse in types: each tile keeps a buffer only for the types that
// actually reached it, so memory follows the types that occur, not the combinatorial number of
// strings. `resolve` keeps the `maxTypeLayers` types with the largest total luminance (ties
// broken by type order, so the result is deterministic) and merges the rest into "other".
//
// Thread safety: concurrent addSample calls are safe when they touch different tiles (the path
// tracer renders whole tiles per task). Algorithms that splat anywhere (MLT) give each thread
// its own Film and `merge` them in a fixed order.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "image.h"
#include "math/vec.h"
#include "path_type.h"

namespace partita {

class ThreadPool;

class Film {
    struct Tile;

  public:
    static constexpr int kTileSize = 16;
    static constexpr const char* kOtherLayer = "other";

    Film(int width, int height);
    ~Film();
    Film(Film&&) noexcept;
    Film& operator=(Film&&) noexcept;

    int width() const { return width_; }
    int height() const { return height_; }
    int tilesX() const { return (width_ + kTileSize - 1) / kTileSize; }
    int tilesY() const { return (height_ + kTileSize - 1) / kTileSize; }

    /// Add `value` of a path of `type` to pixel (x, y). Non-finite values are dropped and counted.
    /// Black values change nothing (and do not register the type); a pixel outside the film is
    /// ignored.
    void addSample(int x, int y, PathType type, Rgb value);

    /// One pixel's place in the film, looked up once, for a renderer that adds many samples to
    /// one pixel in a row (the path tracer: all of a pixel's samples in a pass). add() follows
    /// the rules of addSample. Thread safety as for addSample: per tile.
    class Pixel {
      public:
        void add(PathType type, Rgb value);

      private:
        friend class Film;
        Pixel(Film& film, Tile& tile, int index) : film_(&film), tile_(&tile), index_(index) {}
        Film* film_;
        Tile* tile_;
        int index_;
    };
    /// Pixel (x, y), which must lie inside the film (std::out_of_range otherwise).
    Pixel pixel(int x, int y);

    /// Sum another film of the same size into this one (std::invalid_argument otherwise), the
    /// dropped-sample counts included.
    void merge(const Film& other);
    void clear();

    /// The combined image and the type layers, every value multiplied by `scale` (e.g. 1/spp).
    /// Layers: the `maxTypeLayers` types (a negative count counts as 0) with the largest total
    /// luminance, in decreasing order of it and named by PathType::toString(), then "other"
    /// (always last) if any type was left out. Independent of the order in which types reached
    /// a tile; only a pixel's float sum depends on the order of its own samples. With a `pool`,
    /// the work is spread over its threads, for the same result bit for bit.
    LayeredImage resolve(float scale, int maxTypeLayers, ThreadPool* pool = nullptr) const;
    /// Only the combined image, cheaper than resolve (for previews).
    Image resolveCombined(float scale) const;

    /// Number of distinct path types seen so far and of dropped non-finite samples.
    size_t typeCount() const;
    uint64_t droppedSamples() const;

  private:
    int width_ = 0, height_ = 0;
    std::vector<std::unique_ptr<Tile>> tiles_;
    std::atomic<uint64_t> dropped_{0};  // non-finite samples, counted off the hot path
    Tile& tileFor(int x, int y);
};

}  // namespace partita
