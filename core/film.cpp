// Film storage: a grid of kTileSize x kTileSize tiles. Every tile owns its combined RGB sums,
// per-type sums for the kept types (type_layers.h) that reached it, and one "other" buffer for
// every type that is not kept. Edge tiles are allocated full size so that the hot path indexes
// without clipping.
//
// Per-type sums are sparse twice over. A tile keeps only the types that reached it, found through
// a small hash table (the shipped scenes produce thousands of types, hundreds per tile, so a
// linear search was a hot spot). And a type's sums live in 4 x 4 pixel blocks, allocated when
// the first sample of that type lands in the block: most types are rare, and a full tile buffer
// per (tile, type) cost hundreds of megabytes, and the page faults of touching them cost a tenth
// of the render time. A type's blocks (of every tile) come from one pool of its own, so a
// layer's memory can be given back at once (takeResolved).
//
// Exact sums: a pixel's sums are 64-bit fixed-point integers (Film::kFixedPointBits fraction
// bits). Every sample is rounded once, on its own, to that grid, and integers add exactly, so a
// sum does not depend on the order or the grouping of its additions: a film rendered in one
// process and the merge of any number of shards that rendered parts of it (shard/) hold the
// same bits, and so do films merged in any order. Floats could not do this (a float sum of the
// same samples differs with how they are grouped). The grid step, 2^-28 = 3.7e-9, is below
// anything an image shows; the range, +-2^35 = 3.4e10 per pixel sum, is above what the render
// limits allow (render_settings.h). The arithmetic is modulo 2^64 (unsigned), so even a
// partial sum that leaves the range does not change the final one; a single sample larger than
// kMaxSampleValue is dropped and counted like a non-finite one.
//
// Determinism otherwise: nothing in resolve/merge/typeCount depends on the order in which types
// were first seen in a tile (that order depends on thread scheduling). Type totals are summed
// over tiles in tile order and over pixels in pixel order, in double; the "other" layer adds
// its types in PathType order.
#include "film.h"

#include <algorithm>
#include <array>
#include <bit>
#include <bitset>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <cmath>
#include <cstdlib>
#include <cstring>
#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#endif
#include <functional>
#include <map>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "path_type_bytes.h"
#include "thread_pool.h"

namespace partita {

namespace {

constexpr int kTilePixels = Film::kTileSize * Film::kTileSize;

/// One pixel's RGB sums in fixed point (see the top of the file).
struct FixedRgb {
    std::array<uint64_t, 3> c{};

    /// v on the grid, rounded to nearest (ties to even, the default rounding mode). Film::Pixel
    /// bounds |v| first, so the product fits an int64.
    static uint64_t toFixed(float v) {
        const double scaled = double(v) * double(uint64_t(1) << Film::kFixedPointBits);
#if defined(__SSE2__) && defined(__x86_64__)
        // What llrint computes, as one instruction: without -fno-math-errno the compiler calls
        // libm's llrint (through the PLT, three times a sample) in case it must set errno.
        return uint64_t(_mm_cvtsd_si64(_mm_set_sd(scaled)));
#else
        return uint64_t(std::llrint(scaled));
#endif
    }
    static FixedRgb of(Rgb v) { return {{toFixed(v.x), toFixed(v.y), toFixed(v.z)}}; }
    FixedRgb& operator+=(const FixedRgb& o) {
        for (int i = 0; i < 3; ++i) c[size_t(i)] += o.c[size_t(i)];
        return *this;
    }
    Rgb rgb() const {
        constexpr double step = 1.0 / double(uint64_t(1) << Film::kFixedPointBits);
        return Rgb(float(double(int64_t(c[0])) * step), float(double(int64_t(c[1])) * step),
                   float(double(int64_t(c[2])) * step));
    }
};
static_assert(sizeof(FixedRgb) == Film::kBytesPerSum);
using TilePixels = std::array<FixedRgb, kTilePixels>;

int tileIndex(int x, int y) {
    return (y % Film::kTileSize) * Film::kTileSize + (x % Film::kTileSize);
}

constexpr int kBlockSide = 4;
constexpr int kBlockPixels = kBlockSide * kBlockSide;
constexpr int kBlocksPerRow = Film::kTileSize / kBlockSide;
constexpr int kTileBlocks = kBlocksPerRow * kBlocksPerRow;
using Block = std::array<FixedRgb, kBlockPixels>;

/// The block of tile pixel i (row-major in the tile, so 0 <= i < kTilePixels) and its place in
/// the block. Unsigned: the divisions become shifts.
size_t blockOf(int i) {
    unsigned x = unsigned(i) % Film::kTileSize, y = unsigned(i) / Film::kTileSize;
    return (y / kBlockSide) * kBlocksPerRow + x / kBlockSide;
}
size_t offsetInBlock(int i) {
    unsigned x = unsigned(i) % Film::kTileSize, y = unsigned(i) / Film::kTileSize;
    return (y % kBlockSide) * kBlockSide + x % kBlockSide;
}

/// Zeroed blocks of one buffer kind (one path type, or "other") across every tile, carved out of
/// chunks that grow from 4 to 512 blocks; freed all at once, so that the consuming resolve
/// (Film::takeResolved) gives a layer's memory back as soon as its image is made. Blocks never
/// move. A block is six cache lines and chunks are line-aligned, so blocks of two tiles written
/// by different threads never share a line. Thread-safe: the path tracer's threads allocate in
/// different tiles at once (rarely: a block is allocated once per tile and type).
class BlockPool {
  public:
    Block* allocate() {
        std::lock_guard<std::mutex> lock(mutex_);
        if (used_ == capacity_) {
            capacity_ = chunks_.empty() ? 4 : std::min<size_t>(512, 2 * capacity_);
            chunks_.push_back(zeroedChunk(capacity_));
            used_ = 0;
        }
        return &alignedBlocks(chunks_.back())[used_++].block;
    }
    /// Frees every block (their pointers must not be used again).
    void release() {
        std::lock_guard<std::mutex> lock(mutex_);
        chunks_.clear();
        used_ = capacity_ = 0;
    }

  private:
    struct alignas(64) LineAlignedBlock {
        Block block{};
    };
    static_assert(sizeof(LineAlignedBlock) == sizeof(Block));
    static_assert(std::is_trivially_copyable_v<LineAlignedBlock>);
    using Chunk = std::unique_ptr<void, decltype(&std::free)>;
    /// `blocks` zeroed blocks and a line of slack to align them. From calloc, not new[] and a
    /// clear: memory fresh from the system (most of a large film's) is known to be zero and is
    /// not written once more (the clear was a tenth of reading a shard's film).
    static Chunk zeroedChunk(size_t blocks) {
        void* raw = std::calloc(blocks * sizeof(LineAlignedBlock) + 64, 1);
        if (!raw) throw std::bad_alloc();
        return Chunk(raw, &std::free);
    }
    static LineAlignedBlock* alignedBlocks(const Chunk& chunk) {
        const auto at = reinterpret_cast<uintptr_t>(chunk.get());
        return reinterpret_cast<LineAlignedBlock*>((at + 63) & ~uintptr_t(63));
    }
    std::mutex mutex_;
    std::vector<Chunk> chunks_;
    size_t used_ = 0, capacity_ = 0;
};

}  // namespace

// The film's block pools: one per type that got a buffer somewhere, one for "other".
struct Film::Pools {
    std::mutex mutex;  // guards byType (tiles of several threads add types at once)
    std::map<PathType, std::unique_ptr<BlockPool>> byType;
    BlockPool other;

    BlockPool& forType(PathType type) {
        std::lock_guard<std::mutex> lock(mutex);
        std::unique_ptr<BlockPool>& pool = byType[type];
        if (!pool) pool = std::make_unique<BlockPool>();
        return *pool;
    }
};

// Aligned so that two tiles written by different threads never share a cache line.
struct alignas(64) Film::Tile {
    struct TypeBuffer {
        PathType type;
        std::array<Block*, kTileBlocks> blocks{};  // null where no sample of the type landed
        BlockPool* pool = nullptr;                 // where its blocks come from
    };

    TilePixels combined{};
    std::atomic_flag busy;          // held by addSampleShared while it changes the sums
    std::vector<TypeBuffer> types;  // kept types that reached the tile
    TypeBuffer other;               // every type the film's TypeLayers does not keep
    std::vector<uint32_t> slots;    // open addressing over `types`: 0 = empty, else index + 1
    int slotShift = 64;             // 64 - log2(slots.size())
    // In front of the hash table, per number of scattering vertices, the index into `types` of
    // the last type used with that count: a path reports types of increasing length, so this
    // hits unless two types of equal length (differing in which vertices are specular)
    // alternate.
    std::array<uint32_t, PathType::kMaxScatteringVertices + 1> lastByLength{};
    // Likewise the last type per length that went to "other" (its specular mask; a type is
    // its length and mask), so that a run of samples of one type the film does not keep asks
    // the TypeLayers table once.
    std::array<uint64_t, PathType::kMaxScatteringVertices + 1> lastOtherMask{};
    std::bitset<PathType::kMaxScatteringVertices + 1> hasLastOther;

    /// The buffer of `type`: its own when `layers` keeps it, else "other".
    TypeBuffer& bufferFor(PathType type, const TypeLayers& layers, Pools& pools) {
        uint32_t& last = lastByLength[size_t(type.scatteringVertices())];
        if (last < types.size() && types[last].type == type) return types[last];
        const size_t length = size_t(type.scatteringVertices());
        if (hasLastOther[length] && lastOtherMask[length] == type.specularMask()) return other;
        if (!layers.keeps(type)) {
            lastOtherMask[length] = type.specularMask();
            hasLastOther.set(length);
            return other;
        }
        TypeBuffer& t = find(type, pools);
        last = uint32_t(&t - types.data());
        return t;
    }

    /// The sum of `t` at tile pixel i, its block allocated if needed.
    FixedRgb& sumAt(TypeBuffer& t, int i) {
        Block*& b = t.blocks[blockOf(i)];
        if (!b) b = t.pool->allocate();
        return (*b)[offsetInBlock(i)];
    }

    /// Calls f(i, value) for the pixels of the w x h top-left part of the tile, row by row,
    /// skipping blocks that were never allocated (their pixels are zero).
    template <typename F>
    static void forEachSum(const TypeBuffer& t, int w, int h, F&& f) {
        for (int y = 0; y < h; ++y)
            for (int bx = 0; bx * kBlockSide < w; ++bx) {
                const Block* b = t.blocks[size_t((y / kBlockSide) * kBlocksPerRow + bx)];
                if (!b) continue;
                for (int x = bx * kBlockSide; x < std::min(w, (bx + 1) * kBlockSide); ++x)
                    f(y * Film::kTileSize + x,
                      (*b)[size_t((y % kBlockSide) * kBlockSide + x % kBlockSide)]);
            }
    }

    /// Adds t's unscaled sums, t a buffer of the tile at r, into dst's pixels.
    static void addSums(const TypeBuffer& t, const TileRect& r, Image& dst) {
        forEachSum(t, r.w, r.h, [&](int i, const FixedRgb& v) {
            dst.add(r.x0 + i % kTileSize, r.y0 + i / kTileSize, v.rgb());
        });
    }

    void clear(Pools& pools) {
        combined.fill(FixedRgb{});
        types.clear();
        other = TypeBuffer{};
        other.pool = &pools.other;
        slots.clear();
        slotShift = 64;
        lastByLength.fill(0);
        hasLastOther.reset();
    }

  private:
    // The hash lookup (and insertion), kept out of line so that bufferFor's cache hit inlines.
    [[gnu::noinline]] TypeBuffer& find(PathType type, Pools& pools) {
        if (!slots.empty()) {
            const size_t mask = slots.size() - 1;
            for (size_t s = slotOf(type);; s = (s + 1) & mask) {
                uint32_t e = slots[s];
                if (e == 0) break;
                if (types[e - 1].type == type) return types[e - 1];
            }
        }
        types.push_back({type, {}, &pools.forType(type)});
        if (2 * types.size() > slots.size()) {
            rehash(std::max<size_t>(16, 4 * types.size()));
        } else {
            place(types.size() - 1);
        }
        return types.back();
    }
    size_t slotOf(PathType type) const {
        // Fibonacci hashing of both fields; the high bits of the product index the table.
        uint64_t h = (type.specularMask() ^ uint64_t(type.scatteringVertices()) << 57) *
                     0x9e3779b97f4a7c15ull;
        return size_t(h >> slotShift);
    }
    void place(size_t index) {
        const size_t mask = slots.size() - 1;
        size_t s = slotOf(types[index].type);
        while (slots[s] != 0) s = (s + 1) & mask;
        slots[s] = uint32_t(index + 1);
    }
    void rehash(size_t minSlots) {
        size_t pow2 = 16;
        while (pow2 < minSlots) pow2 *= 2;
        slots.assign(pow2, 0);
        slotShift = 64 - std::countr_zero(pow2);
        for (size_t i = 0; i < types.size(); ++i) place(i);
    }
};

Film::Film(int width, int height, TypeLayers layers)
    : width_(width),
      height_(height),
      layers_(std::move(layers)),
      typeBuffers_(!layers_.keepsNone()),
      pools_(std::make_unique<Pools>()) {
    if (width < 0 || height < 0)
        throw std::invalid_argument("Film: negative size " + std::to_string(width) + "x" +
                                    std::to_string(height));
    tiles_.resize(size_t(tilesX()) * tilesY());
    for (auto& t : tiles_) {
        t = std::make_unique<Tile>();
        t->other.pool = &pools_->other;
    }
}

Film::~Film() = default;

Film::Film(Film&& o) noexcept
    : width_(o.width_),
      height_(o.height_),
      layers_(o.layers_),
      typeBuffers_(o.typeBuffers_),
      pools_(std::move(o.pools_)),
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
        layers_ = o.layers_;
        typeBuffers_ = o.typeBuffers_;
        tiles_ = std::move(o.tiles_);  // before the pools their buffers point into
        pools_ = std::move(o.pools_);
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

namespace {

/// A spin lock on a tile's flag for the few nanoseconds a sample's additions take: the writers
/// are chains on as many threads as there are cores, which rarely meet in one tile.
class SpinLock {
  public:
    explicit SpinLock(std::atomic_flag& flag) : flag_(flag) {
        while (flag_.test_and_set(std::memory_order_acquire))
            while (flag_.test(std::memory_order_relaxed)) {
            }
    }
    ~SpinLock() { flag_.clear(std::memory_order_release); }
    SpinLock(const SpinLock&) = delete;
    SpinLock& operator=(const SpinLock&) = delete;

  private:
    std::atomic_flag& flag_;
};

}  // namespace

void Film::addSampleShared(int x, int y, PathType type, Rgb value) {
    if (unsigned(x) >= unsigned(width_) || unsigned(y) >= unsigned(height_)) return;
    Tile& tile = tileFor(x, y);
    SpinLock lock(tile.busy);
    Pixel(*this, tile, tileIndex(x, y)).add(type, value);
}

Film::Pixel Film::pixel(int x, int y) {
    if (unsigned(x) >= unsigned(width_) || unsigned(y) >= unsigned(height_))
        throw std::out_of_range("Film::pixel: (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") is outside the film");
    return Pixel(*this, tileFor(x, y), tileIndex(x, y));
}

void Film::Pixel::add(PathType type, Rgb value) {
    // One test each for non-finite and too large (a NaN fails every comparison).
    if (!(std::fabs(value.x) <= kMaxSampleValue && std::fabs(value.y) <= kMaxSampleValue &&
          std::fabs(value.z) <= kMaxSampleValue)) {
        film_->dropped_.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    // A black sample changes no sum; skipping it also keeps zero-contribution types from
    // allocating buffers.
    if (isBlack(value)) return;
    const FixedRgb fixed = FixedRgb::of(value);
    tile_->combined[size_t(index_)] += fixed;
    // A film that keeps no type has no "other" either: it would repeat the combined sums.
    if (film_->typeBuffers_)
        tile_->sumAt(tile_->bufferFor(type, film_->layers_, *film_->pools_), index_) += fixed;
}

void Film::merge(const Film& other) {
    if (other.width_ != width_ || other.height_ != height_)
        throw std::invalid_argument("Film::merge: size mismatch (" + std::to_string(width_) + "x" +
                                    std::to_string(height_) + " vs " +
                                    std::to_string(other.width_) + "x" +
                                    std::to_string(other.height_) + ")");
    if (!(other.layers_ == layers_))
        throw std::invalid_argument("Film::merge: the films keep different type layers");
    if (&other == this) {
        // Doubling in place: adding a film to itself.
        for (auto& tile : tiles_) {
            for (auto& p : tile->combined) p += p;
            auto doubleBuffer = [](Tile::TypeBuffer& t) {
                for (Block* b : t.blocks)
                    if (b)
                        for (auto& p : *b) p += p;
            };
            for (auto& t : tile->types) doubleBuffer(t);
            doubleBuffer(tile->other);
        }
        dropped_ += dropped_.load();
        return;
    }
    for (size_t ti = 0; ti < tiles_.size(); ++ti) {
        Tile& dst = *tiles_[ti];
        const Tile& src = *other.tiles_[ti];
        for (int i = 0; i < kTilePixels; ++i) dst.combined[i] += src.combined[i];
        auto add = [&](const Tile::TypeBuffer& from, Tile::TypeBuffer& to) {
            Tile::forEachSum(from, kTileSize, kTileSize,
                             [&](int i, const FixedRgb& v) { dst.sumAt(to, i) += v; });
        };
        for (const auto& t : src.types) add(t, dst.bufferFor(t.type, layers_, *pools_));
        add(src.other, dst.other);
    }
    dropped_.fetch_add(other.dropped_.load(), std::memory_order_relaxed);
}

void Film::clear() {
    auto fresh = std::make_unique<Pools>();
    for (auto& t : tiles_) t->clear(*fresh);
    pools_ = std::move(fresh);
    dropped_ = 0;
}

void Film::release() {
    tiles_.clear();  // before the pools their buffers point into
    pools_ = std::make_unique<Pools>();
    width_ = height_ = 0;
    dropped_ = 0;
#ifdef __GLIBC__
    malloc_trim(0);  // the tiles lie in the heap: their pages go back only when trimmed
#endif
}

Image Film::resolveCombined(float scale) const {
    Image img(width_, height_);
    const int tx = tilesX();
    for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
            const Tile& tile = *tiles_[size_t(y / kTileSize) * tx + x / kTileSize];
            img.set(x, y, tile.combined[size_t(tileIndex(x, y))].rgb() * scale);
        }
    }
    return img;
}

Film::TileRect Film::tileRect(size_t ti) const {
    const int x0 = int(ti % size_t(tilesX())) * kTileSize;
    const int y0 = int(ti / size_t(tilesX())) * kTileSize;
    return {x0, y0, std::min(kTileSize, width_ - x0), std::min(kTileSize, height_ - y0)};
}

void Film::scaleTileRect(const TileRect& r, float scale, Image& dst) const {
    for (int y = r.y0; y < r.y0 + r.h; ++y) {
        float* row = &dst.rgb[(size_t(y) * size_t(width_) + size_t(r.x0)) * 3];
        for (int k = 0; k < r.w * 3; ++k) row[k] *= scale;
    }
}

Image Film::resolveType(PathType type, float scale) const {
    Image img(width_, height_);
    for (size_t ti = 0; ti < tiles_.size(); ++ti) {
        const TileRect r = tileRect(ti);
        for (const auto& t : tiles_[ti]->types)
            if (t.type == type) Tile::addSums(t, r, img);
    }
    // Summed, then scaled, as resolve() does it: the same operations per pixel.
    for (float& v : img.rgb) v *= scale;
    return img;
}

namespace {

/// body(i) for i < count, on the pool's threads when there is one. Callers make every body
/// write only its own entries, so the result is the same with or without a pool.
void forEachIndex(ThreadPool* pool, size_t count, const std::function<void(size_t)>& body) {
    if (pool && count > 1) {
        pool->parallelFor(count, body);
    } else {
        for (size_t i = 0; i < count; ++i) body(i);
    }
}

}  // namespace

std::map<PathType, double> Film::typeLuminance(ThreadPool* pool) const {
    // Per tile (in parallel), then summed over tiles in tile order. std::map keeps the types in
    // PathType order, and the sums run over tiles and pixels in a fixed order, so the totals do
    // not depend on the order in which types reached a tile.
    std::vector<std::vector<std::pair<PathType, double>>> tileTotals(tiles_.size());
    forEachIndex(pool, tiles_.size(), [&](size_t ti) {
        const Tile& tile = *tiles_[ti];
        const TileRect r = tileRect(ti);
        auto& sums = tileTotals[ti];
        sums.reserve(tile.types.size());
        for (const auto& t : tile.types) {
            // Pixels without a block are zero: skipping them leaves the double sum unchanged.
            double sum = 0;
            Tile::forEachSum(t, r.w, r.h,
                             [&](int, const FixedRgb& v) { sum += luminance(v.rgb()); });
            sums.emplace_back(t.type, sum);
        }
    });
    std::map<PathType, double> totals;
    for (const auto& sums : tileTotals)  // a type occurs at most once per tile
        for (const auto& [type, sum] : sums) totals[type] += sum;
    return totals;
}

LayeredImage Film::resolve(float scale, int maxTypeLayers, ThreadPool* pool) const {
    // Every step below is either per tile (each tile writes only its own pixels or its own
    // entry), per layer, or a serial reduction in a fixed order, so the result is the same bit
    // for bit with or without a pool and however the tasks land on threads.

    const LayerOrder order = layerOrder(maxTypeLayers, pool);
    const size_t keep = order.keep;
    const bool hasOther = order.hasOther;
    const std::map<PathType, size_t>& layerOf = order.layerOf;

    // The images, zeroed in parallel (most of the cost of a fresh image is touching its pages).
    LayeredImage out;
    std::vector<Image> layers(keep + (hasOther ? 1 : 0));
    forEachIndex(pool, layers.size() + 1, [&](size_t i) {
        (i == 0 ? out.combined : layers[i - 1]) = Image(width_, height_);
    });

    // Per tile: the combined image, the unscaled layer sums, then every layer pixel of the tile
    // scaled (as scaling whole images after summing: the same operations per pixel).
    forEachIndex(pool, tiles_.size(), [&](size_t ti) {
        const Tile& tile = *tiles_[ti];
        const TileRect r = tileRect(ti);
        for (int y = 0; y < r.h; ++y)
            for (int x = 0; x < r.w; ++x)
                out.combined.set(r.x0 + x, r.y0 + y,
                                 tile.combined[size_t(y * kTileSize + x)].rgb() * scale);
        // Visit the tile's types in PathType order so that "other" sums in a fixed order, the
        // types the film does not keep last.
        std::vector<const Tile::TypeBuffer*> sorted;
        sorted.reserve(tile.types.size());
        for (const auto& t : tile.types) sorted.push_back(&t);
        std::sort(sorted.begin(), sorted.end(),
                  [](const auto* a, const auto* b) { return a->type < b->type; });
        for (const auto* t : sorted) Tile::addSums(*t, r, layers[layerOf.at(t->type)]);
        if (hasOther) Tile::addSums(tile.other, r, layers[keep]);
        for (auto& img : layers) scaleTileRect(r, scale, img);
    });

    out.layers.reserve(layers.size());
    for (size_t i = 0; i < layers.size(); ++i)
        out.layers.push_back({order.name(i), std::move(layers[i])});
    return out;
}

Film::LayerOrder Film::layerOrder(int maxTypeLayers, ThreadPool* pool) const {
    // Rank: largest total first, ties by PathType order (stable sort over the ordered map).
    const std::map<PathType, double> totals = typeLuminance(pool);
    LayerOrder order;
    order.ranked.assign(totals.begin(), totals.end());
    std::stable_sort(order.ranked.begin(), order.ranked.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    order.keep = std::min(order.ranked.size(), size_t(std::max(0, maxTypeLayers)));
    bool otherBuffers = false;  // a type the film does not keep reached some tile
    for (const auto& tile : tiles_)
        for (const Block* b : tile->other.blocks) otherBuffers |= b != nullptr;
    order.hasOther = order.ranked.size() > order.keep || otherBuffers;
    for (size_t i = 0; i < order.ranked.size(); ++i)
        order.layerOf[order.ranked[i].first] = std::min(i, order.keep);
    return order;
}

std::string Film::LayerOrder::name(size_t layer) const {
    return layer < keep ? ranked[layer].first.toString() : std::string(kOtherLayer);
}

LayeredImage Film::takeResolved(float scale, int maxTypeLayers, ThreadPool* pool) {
    // resolve()'s image bit for bit (the same additions per pixel, in the same order), made one
    // layer at a time; each layer's blocks are given back as soon as its image is made, so the
    // peak is the film and one layer rather than the film and every layer.
    const LayerOrder order = layerOrder(maxTypeLayers, pool);
    const size_t layerCount = order.keep + (order.hasOther ? 1 : 0);
    // Per tile, its buffers by (layer, PathType): each layer's in the order resolve adds them.
    std::vector<std::vector<std::pair<size_t, const Tile::TypeBuffer*>>> byLayer(tiles_.size());
    forEachIndex(pool, tiles_.size(), [&](size_t ti) {
        auto& list = byLayer[ti];
        for (const auto& t : tiles_[ti]->types) list.emplace_back(order.layerOf.at(t.type), &t);
        std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) {
            return a.first != b.first ? a.first < b.first : a.second->type < b.second->type;
        });
    });
    LayeredImage out;
    out.combined = resolveCombined(scale);
    for (size_t layer = 0; layer < layerCount; ++layer) {
        Image img(width_, height_);
        forEachIndex(pool, tiles_.size(), [&](size_t ti) {
            const Tile& tile = *tiles_[ti];
            const TileRect r = tileRect(ti);
            const auto& list = byLayer[ti];
            auto first = std::lower_bound(list.begin(), list.end(), layer,
                                          [](const auto& e, size_t l) { return e.first < l; });
            for (auto it = first; it != list.end() && it->first == layer; ++it)
                Tile::addSums(*it->second, r, img);
            if (layer == order.keep) Tile::addSums(tile.other, r, img);
            scaleTileRect(r, scale, img);
        });
        out.layers.push_back({order.name(layer), std::move(img)});
        releaseLayer(order, layer);
    }
    clear();
    return out;
}

void Film::releaseLayer(const LayerOrder& order, size_t layer) {
    // The tiles' block pointers into these pools are not read again: the film is cleared next.
    for (const auto& [type, l] : order.layerOf)
        if (l == layer) pools_->byType.erase(type);
    if (layer == order.keep) pools_->other.release();
#ifdef __GLIBC__
    malloc_trim(0);  // freed chunks below the mmap threshold go back to the system too
#endif
}

size_t Film::typeCount() const {
    std::vector<PathType> all;
    for (const auto& tile : tiles_)
        for (const auto& t : tile->types) all.push_back(t.type);
    std::sort(all.begin(), all.end());
    return size_t(std::unique(all.begin(), all.end()) - all.begin());
}

size_t Film::maxBuffersPerTile() const {
    size_t most = 0;
    for (const auto& tile : tiles_) {
        bool other = false;
        for (const Block* b : tile->other.blocks) other |= b != nullptr;
        most = std::max(most, 1 + tile->types.size() + (other ? 1 : 0));
    }
    return most;
}

uint64_t Film::droppedSamples() const { return dropped_.load(std::memory_order_relaxed); }

namespace {
constexpr uint32_t kFilmMagic = 0x4d4c4650;  // "PFLM"
constexpr uint32_t kFilmVersion = 4;  // 2: sums as zigzag varints; 3: type layers and "other";
                                      // 4: tiles' byte counts first

void putSums(ByteWriter& w, const FixedRgb* sums, size_t count) {
    w.putSignedVarints(3 * count, [&](size_t i) { return int64_t(sums[i / 3].c[i % 3]); });
}
void getSums(ByteReader& r, FixedRgb* sums, size_t count) {
    r.getSignedVarints(3 * count, [&](size_t i, int64_t v) { sums[i / 3].c[i % 3] = uint64_t(v); });
}

// Blocks of one buffer: a bit mask of the allocated ones, then those blocks' sums.
void putBlocks(ByteWriter& w, const std::array<Block*, kTileBlocks>& blocks) {
    static_assert(kTileBlocks == 16, "the block mask is 16 bits");
    uint16_t mask = 0;
    for (size_t b = 0; b < blocks.size(); ++b)
        if (blocks[b]) mask = uint16_t(mask | (1u << b));
    w.put(mask);
    for (const Block* b : blocks)
        if (b) putSums(w, b->data(), b->size());
}
void getBlocks(ByteReader& r, std::array<Block*, kTileBlocks>& blocks, BlockPool& pool) {
    const uint16_t mask = r.get<uint16_t>();
    for (size_t b = 0; b < blocks.size(); ++b) {
        if (!((mask >> b) & 1u)) continue;
        blocks[b] = pool.allocate();
        getSums(r, blocks[b]->data(), blocks[b]->size());
    }
}

/// body(t) for every tile t, on `threads` threads (one: in order, on this thread).
void forEachTile(size_t tiles, int threads, const std::function<void(size_t)>& body) {
    if (threads <= 1) {
        for (size_t t = 0; t < tiles; ++t) body(t);
        return;
    }
    ThreadPool(threads).parallelFor(tiles, body);
}

}  // namespace

// The type layers, each tile's byte count, then per tile: the combined sums, the tile's types in
// PathType order (so that the bytes do not depend on the order in which types reached it), each
// with its blocks, and the "other" buffer's blocks. Sums are zigzag varints: most are zero or far
// below 2^63. The byte counts let tiles be written and read in parallel (a 1280x720 film of a
// shard holds ~150 MB of varints: one thread took ~2 s to read them).
std::vector<std::vector<uint8_t>> Film::serializePieces(int threads) const {
    std::vector<std::vector<uint8_t>> pieces(1 + tiles_.size());
    forEachTile(tiles_.size(), threads, [&](size_t t) {
        ByteWriter w;
        putTile(w, *tiles_[t]);
        pieces[1 + t] = std::move(w.bytes);
    });
    ByteWriter w;
    w.putHeader(kFilmMagic, kFilmVersion);
    w.put(int32_t(width_));
    w.put(int32_t(height_));
    w.put(uint64_t(dropped_.load()));
    layers_.serialize(w);
    for (size_t t = 1; t < pieces.size(); ++t) w.put(uint32_t(pieces[t].size()));
    pieces[0] = std::move(w.bytes);
    return pieces;
}

std::vector<uint8_t> Film::serialize(int threads) const {
    std::vector<std::vector<uint8_t>> pieces = serializePieces(threads);
    size_t total = 0;
    for (const auto& p : pieces) total += p.size();
    std::vector<uint8_t> bytes;
    bytes.reserve(total);
    for (auto& p : pieces) {
        bytes.insert(bytes.end(), p.begin(), p.end());
        std::vector<uint8_t>().swap(p);  // given back as it is copied
    }
    return bytes;
}

Film Film::deserialize(std::span<const uint8_t> bytes, int threads) {
    ByteReader r(bytes, "film");
    r.expectHeader(kFilmMagic, kFilmVersion, "film");
    int32_t w = r.get<int32_t>(), h = r.get<int32_t>();
    if (w < 0 || h < 0 || int64_t(w) * h > (int64_t(1) << 28)) r.fail("bad size");
    const uint64_t dropped = r.get<uint64_t>();
    Film film(w, h, TypeLayers::deserialize(r));
    film.dropped_ = dropped;
    std::vector<std::span<const uint8_t>> tileBytes(film.tiles_.size());
    std::vector<uint32_t> sizes(film.tiles_.size());
    for (uint32_t& size : sizes) size = r.get<uint32_t>();
    for (size_t t = 0; t < sizes.size(); ++t) tileBytes[t] = r.getRaw(sizes[t]);
    if (!r.atEnd()) r.fail("trailing bytes");
    forEachTile(film.tiles_.size(), threads, [&](size_t t) {
        ByteReader tr(tileBytes[t], "film");
        film.getTile(tr, *film.tiles_[t]);
        if (!tr.atEnd()) tr.fail("trailing bytes in a tile");
    });
    return film;
}

void Film::putTile(ByteWriter& w, const Tile& tile) const {
    putSums(w, tile.combined.data(), tile.combined.size());
    std::vector<const Tile::TypeBuffer*> sorted;
    for (const auto& t : tile.types) sorted.push_back(&t);
    std::sort(sorted.begin(), sorted.end(),
              [](const auto* a, const auto* b) { return a->type < b->type; });
    w.put(uint32_t(sorted.size()));
    for (const auto* t : sorted) {
        putPathType(w, t->type);
        putBlocks(w, t->blocks);
    }
    putBlocks(w, tile.other.blocks);
}

void Film::getTile(ByteReader& r, Tile& tile) {
    getSums(r, tile.combined.data(), tile.combined.size());
    uint32_t types = r.get<uint32_t>();
    for (uint32_t k = 0; k < types; ++k) {
        const PathType type = getPathType(r);
        if (!tile.types.empty() && !(tile.types.back().type < type)) r.fail("types out of order");
        if (!layers_.keeps(type)) r.fail("a type the film does not keep");
        Tile::TypeBuffer& buffer = tile.bufferFor(type, layers_, *pools_);
        getBlocks(r, buffer.blocks, *buffer.pool);
    }
    getBlocks(r, tile.other.blocks, *tile.other.pool);
}

}  // namespace partita
