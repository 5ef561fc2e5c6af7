// The film: accumulates path contributions into a combined image and one image per path type.
//
// Which types get a buffer of their own is fixed when the film is made (type_layers.h): a set
// chosen before the render, every other type summed into one "other" buffer, so a tile holds at
// most (kept types + 2) buffers whatever the scene and the samples (issue #24); or every type
// that occurs (TypeLayers::every(), tests and tools). Storage is tiled and sparse in types: each
// tile keeps a buffer only for the kept types that actually reached it. `resolve` keeps the
// `maxTypeLayers` of them with the largest total luminance (ties broken by type order, so the
// result is deterministic) and merges the rest, and the "other" buffer, into "other".
//
// Thread safety: concurrent addSample calls are safe when they touch different tiles (the path
// tracer renders whole tiles per task). Writers that splat anywhere (the MCMC chains) use
// addSampleShared, which locks the tile it writes.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "image.h"
#include "math/vec.h"
#include "path_type.h"
#include "type_layers.h"

namespace partita {

class ByteReader;
class ByteWriter;
class ThreadPool;

class Film {
    struct Tile;

  public:
    static constexpr int kTileSize = 16;
    /// Sums are exact 64-bit fixed point with this many fraction bits (film.cpp): the same bits
    /// however the samples are grouped, so shards merge into the one-process film exactly.
    static constexpr int kFixedPointBits = 28;
    /// A sample component above this is dropped (counted with the non-finite ones): 2^33, a
    /// quarter of what one sum can hold.
    static constexpr float kMaxSampleValue = 8589934592.0f;
    /// Bytes of one pixel's sums (RGB) in one buffer: the combined one or a type's.
    static constexpr int kBytesPerSum = 24;
    static constexpr const char* kOtherLayer = "other";

    /// A film keeping a layer of the types `layers` names (every type by default).
    Film(int width, int height, TypeLayers layers = TypeLayers::every());
    ~Film();
    Film(Film&&) noexcept;
    Film& operator=(Film&&) noexcept;

    int width() const { return width_; }
    int height() const { return height_; }
    int tilesX() const { return (width_ + kTileSize - 1) / kTileSize; }
    int tilesY() const { return (height_ + kTileSize - 1) / kTileSize; }
    const TypeLayers& layers() const { return layers_; }

    /// Add `value` of a path of `type` to pixel (x, y). Non-finite values (and components above
    /// kMaxSampleValue) are dropped and counted.
    /// Black values change nothing (and do not register the type); a pixel outside the film is
    /// ignored.
    void addSample(int x, int y, PathType type, Rgb value);

    /// addSample for writers that share tiles: MCMC chains, whose splats land anywhere, add
    /// from every thread at once. The tile's lock is held while its sums change, so this is
    /// safe against other addSampleShared calls (not against addSample, merge or resolve). The
    /// sums are exact, so the film does not depend on which thread got a tile first.
    void addSampleShared(int x, int y, PathType type, Rgb value);

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

    /// Sum another film of the same size and type layers into this one (std::invalid_argument
    /// otherwise), the dropped-sample counts included.
    void merge(const Film& other);
    void clear();
    /// Gives every sum's memory back to the system (a film whose image has been made): the film
    /// is 0x0 afterwards. clear() keeps the memory for more samples.
    void release();

    /// The combined image and the type layers, every value multiplied by `scale` (e.g. 1/spp).
    /// Layers: the `maxTypeLayers` types (a negative count counts as 0) with the largest total
    /// luminance, in decreasing order of it and named by PathType::toString(), then "other"
    /// (always last) if any type was left out. Independent of the order in which types reached
    /// a tile or of samples within a pixel (the sums are exact). With a `pool`,
    /// the work is spread over its threads, for the same result bit for bit.
    LayeredImage resolve(float scale, int maxTypeLayers, ThreadPool* pool = nullptr) const;
    /// resolve()'s image bit for bit, consuming the film: each layer's memory is given back as
    /// soon as its image is made (a render's final image: its peak is the film and one layer,
    /// not the film and every layer). The film is empty afterwards.
    LayeredImage takeResolved(float scale, int maxTypeLayers, ThreadPool* pool = nullptr);
    /// Only the combined image, cheaper than resolve (for previews).
    Image resolveCombined(float scale) const;
    /// Only the sums of one kept type, scaled: resolve()'s layer of it where resolve keeps it
    /// as a layer of its own (black for a type the film does not keep or that never occurred).
    /// One image's memory, not every layer's (the per-pixel pilot reads its partitions' pairs
    /// of layers one pair at a time).
    Image resolveType(PathType type, float scale) const;

    /// A versioned binary form of every sum (all types, exact), for a shard's result (shard/);
    /// deserialize throws std::invalid_argument on anything else (truncated, another version).
    /// Equal films give equal bytes, whatever order types reached their tiles in.
    /// With `threads` > 1, the tiles are written (read) on that many threads: the same bytes
    /// (film).
    std::vector<uint8_t> serialize(int threads = 1) const;
    /// serialize()'s bytes in pieces (the header, then each tile's), to be written or
    /// compressed one after another without copying them into one buffer first.
    std::vector<std::vector<uint8_t>> serializePieces(int threads = 1) const;
    static Film deserialize(std::span<const uint8_t> bytes, int threads = 1);

    /// Per kept type that occurred, the total luminance of its sums (unscaled), in PathType
    /// order; the types in "other" are not told apart. The same with or without a `pool`.
    std::map<PathType, double> typeLuminance(ThreadPool* pool = nullptr) const;

    /// Number of distinct kept path types seen so far and of dropped non-finite samples.
    size_t typeCount() const;
    /// The most sum buffers one tile holds: its combined buffer, its kept types' and its
    /// "other" buffer when a sample landed there (at most types().size() + 2 when bounded).
    size_t maxBuffersPerTile() const;
    uint64_t droppedSamples() const;

  private:
    struct Pools;
    /// The layers resolve makes: the kept types ranked by total luminance (ties by PathType
    /// order), the first `keep` of them layers of their own, then "other" when anything is left.
    struct LayerOrder {
        std::vector<std::pair<PathType, double>> ranked;
        size_t keep = 0;
        bool hasOther = false;
        std::map<PathType, size_t> layerOf;  // 0..keep-1, or keep for "other"
        std::string name(size_t layer) const;
    };
    LayerOrder layerOrder(int maxTypeLayers, ThreadPool* pool) const;
    /// Tile ti's pixels: its top-left corner and its size (edge tiles are partial).
    struct TileRect {
        int x0, y0, w, h;
    };
    TileRect tileRect(size_t ti) const;
    /// Multiplies dst's pixels inside r by scale.
    void scaleTileRect(const TileRect& r, float scale, Image& dst) const;
    /// Frees the blocks of the types of `layer` (takeResolved).
    void releaseLayer(const LayerOrder& order, size_t layer);
    /// One tile's part of serialize(), and its reading back into an empty tile.
    void putTile(ByteWriter& w, const Tile& tile) const;
    void getTile(ByteReader& r, Tile& tile);
    int width_ = 0, height_ = 0;
    TypeLayers layers_;
    bool typeBuffers_ = true;       // false when layers_ keeps no type: the combined sums only
    std::unique_ptr<Pools> pools_;  // the type buffers' blocks (film.cpp)
    std::vector<std::unique_ptr<Tile>> tiles_;
    std::atomic<uint64_t> dropped_{0};  // non-finite samples, counted off the hot path
    Tile& tileFor(int x, int y);
};

}  // namespace partita
