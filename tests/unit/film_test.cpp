// Tests of the tiled, per-type film.
//
// Several tests compare films bytewise after adding the same samples in different orders or
// through merge. The film's sums are exact (fixed point), so that holds for any values; the
// older tests use dyadic values (multiples of 1/64), whose float sums are exact too, and check
// that nothing *else* (tile type order, thread scheduling, "other", ranking) depends on order;
// Film.SumsDoNotDependOnGrouping checks the exactness itself with arbitrary values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <thread>
#include <vector>

#include "film.h"
#include "thread_pool.h"

namespace partita {
namespace {

struct Sample {
    int x, y;
    PathType type;
    Rgb value;
};

PathType typeFromString(const char* s) {
    PathType t;
    EXPECT_TRUE(PathType::parse(s, t)) << s;
    return t;
}

std::vector<PathType> someTypes() {
    std::vector<PathType> out;
    for (const char* s : {"LE", "LDE", "LSE", "LDDE", "LSDE", "LDSE", "LSSDE", "LDSDE"})
        out.push_back(typeFromString(s));
    return out;
}

/// Random samples; with `dyadic` every component is k/64 for k in [1, 1024), so sums of a few
/// of them per pixel are exact in float.
std::vector<Sample> randomSamples(int w, int h, size_t n, uint32_t seed, bool dyadic) {
    std::mt19937 rng(seed);
    const auto types = someTypes();
    std::uniform_int_distribution<int> dx(0, w - 1), dy(0, h - 1), dt(0, int(types.size()) - 1),
        dk(1, 1023);
    std::uniform_real_distribution<float> dv(0.0f, 3.0f);
    std::vector<Sample> out;
    for (size_t i = 0; i < n; ++i) {
        Sample s{dx(rng), dy(rng), types[dt(rng)], {}};
        if (dyadic)
            s.value = {dk(rng) / 64.0f, dk(rng) / 64.0f, dk(rng) / 64.0f};
        else
            s.value = {dv(rng), dv(rng), dv(rng)};
        out.push_back(s);
    }
    return out;
}

void addAll(Film& film, const std::vector<Sample>& samples) {
    for (const auto& s : samples) film.addSample(s.x, s.y, s.type, s.value);
}

int tileOf(const Film& film, const Sample& s) {
    return (s.y / Film::kTileSize) * film.tilesX() + s.x / Film::kTileSize;
}

/// Add samples from `threads` threads, thread t taking the tiles with index % threads == t (so
/// no two threads touch the same tile), each in the order of `samples`.
void addConcurrently(Film& film, const std::vector<Sample>& samples, int threads, int rotate = 0) {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) {
        pool.emplace_back([&, t] {
            for (const auto& s : samples)
                if ((tileOf(film, s) + rotate) % threads == t)
                    film.addSample(s.x, s.y, s.type, s.value);
        });
    }
    for (auto& th : pool) th.join();
}

bool bytewiseEqual(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
           (a.rgb.empty() ||  // memcmp of null pointers is undefined, even for 0 bytes
            std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0);
}

void expectBytewiseEqual(const LayeredImage& a, const LayeredImage& b) {
    EXPECT_TRUE(bytewiseEqual(a.combined, b.combined));
    ASSERT_EQ(a.layers.size(), b.layers.size());
    for (size_t i = 0; i < a.layers.size(); ++i) {
        EXPECT_EQ(a.layers[i].name, b.layers[i].name);
        EXPECT_TRUE(bytewiseEqual(a.layers[i].image, b.layers[i].image)) << a.layers[i].name;
    }
}

double totalLuminance(const Image& img) {
    double s = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) s += luminance(img.at(x, y));
    return s;
}

TEST(Film, LayersSumToCombined) {
    // 37x23: edge tiles are partial in both directions.
    const int w = 37, h = 23;
    Film film(w, h);
    const auto samples = randomSamples(w, h, 20000, 1, /*dyadic=*/false);
    addAll(film, samples);
    const float scale = 1.0f / 7.0f;
    const LayeredImage img = film.resolve(scale, 100);
    ASSERT_EQ(img.layers.size(), someTypes().size());
    ASSERT_EQ(img.layer(Film::kOtherLayer), nullptr);

    // Tolerance. The combined buffer sums a pixel's n samples in arrival order; each layer sums
    // its own subset; resolve scales both; the check adds up the L layers. Every float add or
    // multiply rounds with relative error <= u = 2^-24 of its result, and all partial sums are
    // bounded by M = the sum of |value| over the pixel's samples, so both sides are within
    // about (n + L + 2) u M of the exact sum. Here n is about 20000 / (37 * 23) ~ 24 samples
    // per pixel (a Poisson tail up to ~50) and L = 8, so the error is below ~60 u M ~ 4e-6 M:
    // a relative 1e-5 of the combined value holds with margin because the values here are
    // non-negative (|combined| == M). The absolute term, a few ulps of M, covers the general
    // case where positive and negative contributions cancel and |combined| << M.
    double worst = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const Rgb c = img.combined.at(x, y);
            for (int k = 0; k < 3; ++k) {
                double sum = 0, magnitude = 0;
                for (const auto& l : img.layers) {
                    sum += l.image.at(x, y)[k];
                    magnitude += std::abs(l.image.at(x, y)[k]);
                }
                const double tol = 1e-5 * std::abs(c[k]) + 8 * FLT_EPSILON * magnitude;
                EXPECT_NEAR(sum, c[k], tol) << "pixel " << x << "," << y << " channel " << k;
                worst = std::max(worst, std::abs(sum - c[k]) / std::max(1e-30, magnitude));
            }
        }
    }
    EXPECT_LT(worst, 1e-5);

    // resolveCombined is the same image as resolve's combined.
    EXPECT_TRUE(bytewiseEqual(film.resolveCombined(scale), img.combined));
}

TEST(Film, ResolveTypeGivesResolvesLayerOfThatType) {
    const int w = 37, h = 23;
    Film film(w, h);
    addAll(film, randomSamples(w, h, 20000, 3, /*dyadic=*/false));
    const float scale = 1.0f / 5.0f;
    const LayeredImage img = film.resolve(scale, 100);
    for (const PathType& type : someTypes()) {
        const Image* layer = img.layer(type.toString());
        ASSERT_NE(layer, nullptr) << type.toString();
        EXPECT_TRUE(bytewiseEqual(film.resolveType(type, scale), *layer)) << type.toString();
    }
    // A type that never occurred: black.
    PathType absent;
    for (int i = 0; i < 40; ++i) absent = absent.withVertex(true);
    const Image black = film.resolveType(absent, scale);
    EXPECT_TRUE(std::all_of(black.rgb.begin(), black.rgb.end(), [](float v) { return v == 0; }));
}

TEST(Film, LayersAreSortedByTotalAndNamedByType) {
    Film film(20, 20);
    const auto types = someTypes();
    // Type i gets total luminance proportional to (i + 1): the last type is the brightest.
    for (size_t i = 0; i < types.size(); ++i)
        for (int p = 0; p < 10; ++p)
            film.addSample(int(p * 2), int(i * 2), types[i], Rgb(float(i + 1)));
    const LayeredImage img = film.resolve(1.0f, 100);
    ASSERT_EQ(img.layers.size(), types.size());
    for (size_t i = 0; i < types.size(); ++i)
        EXPECT_EQ(img.layers[i].name, types[types.size() - 1 - i].toString());
    for (size_t i = 1; i < img.layers.size(); ++i)
        EXPECT_GE(totalLuminance(img.layers[i - 1].image), totalLuminance(img.layers[i].image));
}

TEST(Film, TiesAreBrokenByPathTypeOrder) {
    const auto types = someTypes();
    auto resolveWithOrder = [&](bool reversed) {
        Film film(8, 8);
        std::vector<PathType> order = types;
        if (reversed) std::reverse(order.begin(), order.end());
        // Every type gets the same total, each in its own pixel, added in `order`.
        for (PathType t : order) {
            const int x = int(std::find(types.begin(), types.end(), t) - types.begin());
            film.addSample(x, 0, t, Rgb(0.5f));
        }
        return film.resolve(1.0f, 3);
    };
    const LayeredImage a = resolveWithOrder(false), b = resolveWithOrder(true);
    std::vector<PathType> sorted = types;
    std::sort(sorted.begin(), sorted.end());
    ASSERT_EQ(a.layers.size(), 4u);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(a.layers[i].name, sorted[i].toString());
    EXPECT_EQ(a.layers[3].name, Film::kOtherLayer);
    expectBytewiseEqual(a, b);
}

TEST(Film, OtherHoldsExactlyTheRest) {
    const int w = 40, h = 30;
    const auto samples = randomSamples(w, h, 3000, 2, /*dyadic=*/true);
    Film film(w, h);
    addAll(film, samples);
    const int keep = 3;
    const LayeredImage img = film.resolve(1.0f, keep);
    ASSERT_EQ(img.layers.size(), size_t(keep) + 1);
    EXPECT_EQ(img.layers.back().name, Film::kOtherLayer);

    // Per-type reference sums (exact: dyadic values) and totals.
    std::map<std::string, Image> perType;
    for (const auto& s : samples) {
        auto it = perType.try_emplace(s.type.toString(), w, h).first;
        it->second.add(s.x, s.y, s.value);
    }
    ASSERT_EQ(perType.size(), film.typeCount());
    std::vector<std::pair<double, std::string>> totals;
    for (const auto& [name, image] : perType) totals.push_back({totalLuminance(image), name});
    std::sort(totals.begin(), totals.end(),
              [](const auto& a, const auto& b) { return a.first > b.first; });

    Image rest(w, h);
    for (size_t i = 0; i < totals.size(); ++i) {
        const Image& ref = perType.at(totals[i].second);
        if (i < size_t(keep)) {
            EXPECT_EQ(img.layers[i].name, totals[i].second);
            EXPECT_TRUE(bytewiseEqual(img.layers[i].image, ref)) << totals[i].second;
        } else {
            for (size_t k = 0; k < rest.rgb.size(); ++k) rest.rgb[k] += ref.rgb[k];
        }
    }
    EXPECT_TRUE(bytewiseEqual(img.layers.back().image, rest));

    // maxTypeLayers 0: everything is "other", equal to the combined image.
    const LayeredImage none = film.resolve(1.0f, 0);
    ASSERT_EQ(none.layers.size(), 1u);
    EXPECT_EQ(none.layers[0].name, Film::kOtherLayer);
    EXPECT_TRUE(bytewiseEqual(none.layers[0].image, none.combined));

    // Exactly as many types as layers: no "other".
    const LayeredImage all = film.resolve(1.0f, int(film.typeCount()));
    EXPECT_EQ(all.layer(Film::kOtherLayer), nullptr);
    EXPECT_EQ(all.layers.size(), film.typeCount());
}

TEST(Film, ResolveIsIndependentOfSampleOrder) {
    const int w = 50, h = 35;
    const auto samples = randomSamples(w, h, 6000, 3, /*dyadic=*/true);
    std::vector<Sample> shuffled = samples;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(99));

    Film a(w, h), b(w, h);
    addConcurrently(a, samples, 2, 0);
    addConcurrently(b, shuffled, 2, 1);  // the other thread takes each tile, other order
    EXPECT_EQ(a.typeCount(), b.typeCount());
    for (int keep : {0, 2, 5, 100})
        expectBytewiseEqual(a.resolve(0.25f, keep), b.resolve(0.25f, keep));
}

TEST(Film, MergeEqualsAddingEverythingIntoOneFilm) {
    const int w = 33, h = 17;
    const auto samples = randomSamples(w, h, 4000, 4, /*dyadic=*/true);
    Film all(w, h), first(w, h), second(w, h);
    addAll(all, samples);
    for (size_t i = 0; i < samples.size(); ++i) {
        const auto& s = samples[i];
        (i % 3 == 0 ? first : second).addSample(s.x, s.y, s.type, s.value);
    }
    first.addSample(0, 0, PathType(), Rgb(NAN));
    second.addSample(1, 1, PathType(), Rgb(INFINITY));
    first.merge(second);
    EXPECT_EQ(first.typeCount(), all.typeCount());
    EXPECT_EQ(first.droppedSamples(), 2u);
    for (int keep : {0, 3, 100})
        expectBytewiseEqual(first.resolve(1.0f, keep), all.resolve(1.0f, keep));

    Film wrongSize(w + 1, h);
    EXPECT_THROW(first.merge(wrongSize), std::invalid_argument);
}

// What sharding relies on (shard/): the same samples split into any number of films, each
// filled in its own order, merge in any order into the bits of the one film, for arbitrary
// (non-dyadic) values, many per pixel, and magnitudes far apart.
TEST(Film, SumsDoNotDependOnGrouping) {
    const int w = 37, h = 21;
    std::vector<Sample> samples = randomSamples(w, h, 60000, 21, /*dyadic=*/false);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> exponent(-12.0f, 8.0f);
    for (auto& s : samples) s.value = s.value * std::exp2(exponent(rng));
    Film one(w, h);
    addAll(one, samples);
    for (int parts : {2, 7}) {
        std::vector<Film> films;
        for (int k = 0; k < parts; ++k) films.emplace_back(w, h);
        std::vector<Sample> shuffled = samples;
        std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(uint32_t(parts)));
        for (size_t i = 0; i < shuffled.size(); ++i) {
            const Sample& s = shuffled[i];
            films[(i * 31) % size_t(parts)].addSample(s.x, s.y, s.type, s.value);
        }
        Film merged(w, h);
        std::vector<int> order(static_cast<size_t>(parts));
        for (int k = 0; k < parts; ++k) order[size_t(k)] = k;
        std::shuffle(order.begin(), order.end(), std::mt19937(77));
        for (int k : order) merged.merge(films[size_t(k)]);
        SCOPED_TRACE(testing::Message() << parts << " parts");
        EXPECT_EQ(merged.serialize(), one.serialize());
        expectBytewiseEqual(merged.resolve(0.37f, 3), one.resolve(0.37f, 3));
    }
    // A float sum of the same values does depend on the order (so the check above can fail).
    float forward = 0, backward = 0;
    for (const auto& s : samples) forward += s.value.x;
    for (auto it = samples.rbegin(); it != samples.rend(); ++it) backward += it->value.x;
    EXPECT_NE(forward, backward);
}

TEST(Film, FixedPointSumsAreCloseToDoubleSums) {
    // The rounding of each sample to 2^-28 is far below what an image shows.
    Film film(1, 1);
    double sum = 0;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> v(0.0f, 1e-3f);
    for (int i = 0; i < 100000; ++i) {
        float x = v(rng);
        film.addSample(0, 0, PathType(), Rgb(x));
        sum += double(x);
    }
    const float got = film.resolveCombined(1.0f).at(0, 0).x;
    EXPECT_NEAR(got, sum, 100000 * std::exp2(-29.0) + sum * 1e-7);
    // A sample beyond the range of a sum is dropped like a non-finite one.
    film.addSample(0, 0, PathType(), Rgb(1e10f));
    EXPECT_EQ(film.droppedSamples(), 1u);
    EXPECT_EQ(film.resolveCombined(1.0f).at(0, 0).x, got);
}

TEST(Film, SerializeRoundTripsAndRefusesDamage) {
    const int w = 40, h = 19;
    Film film(w, h);
    addAll(film, randomSamples(w, h, 5000, 8, /*dyadic=*/false));
    film.addSample(1, 1, PathType(), Rgb(NAN));
    const std::vector<uint8_t> bytes = film.serialize();
    Film back = Film::deserialize(bytes);
    EXPECT_EQ(back.width(), w);
    EXPECT_EQ(back.height(), h);
    EXPECT_EQ(back.droppedSamples(), 1u);
    EXPECT_EQ(back.typeCount(), film.typeCount());
    EXPECT_EQ(back.serialize(), bytes);
    expectBytewiseEqual(back.resolve(0.5f, 4), film.resolve(0.5f, 4));
    // Tiles written and read on several threads: the same bytes and the same film.
    EXPECT_EQ(film.serialize(3), bytes);
    EXPECT_EQ(Film::deserialize(bytes, 3).serialize(), bytes);

    std::vector<uint8_t> truncated(bytes.begin(), bytes.end() - 1);
    EXPECT_THROW(Film::deserialize(truncated), std::invalid_argument);
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0);
    EXPECT_THROW(Film::deserialize(longer), std::invalid_argument);
    std::vector<uint8_t> otherVersion = bytes;
    otherVersion[4] ^= 0x7f;
    EXPECT_THROW(Film::deserialize(otherVersion), std::invalid_argument);
    EXPECT_THROW(Film::deserialize(std::vector<uint8_t>(16, 0)), std::invalid_argument);
}

TEST(Film, NonFiniteSamplesAreDroppedAndCounted) {
    Film film(16, 16);
    const PathType lde = typeFromString("LDE"), lse = typeFromString("LSE");
    film.addSample(3, 4, lde, {1.0f, 2.0f, 3.0f});
    const float nan = std::numeric_limits<float>::quiet_NaN(),
                inf = std::numeric_limits<float>::infinity();
    film.addSample(3, 4, lde, {nan, 0, 0});
    film.addSample(3, 4, lse, {0, inf, 0});
    film.addSample(5, 5, lse, {0, 0, -inf});
    film.addSample(5, 5, lse, {-inf, -inf, -inf});
    EXPECT_EQ(film.droppedSamples(), 4u);
    EXPECT_EQ(film.typeCount(), 1u);  // LSE only ever came with non-finite values

    const LayeredImage img = film.resolve(1.0f, 10);
    EXPECT_EQ(img.combined.at(3, 4), Rgb(1.0f, 2.0f, 3.0f));
    EXPECT_EQ(img.combined.at(5, 5), Rgb(0.0f));
    ASSERT_EQ(img.layers.size(), 1u);
    EXPECT_EQ(img.layers[0].name, "LDE");
    for (float v : img.combined.rgb) EXPECT_TRUE(std::isfinite(v));

    film.clear();
    EXPECT_EQ(film.droppedSamples(), 0u);
    EXPECT_EQ(film.typeCount(), 0u);
    EXPECT_EQ(film.resolve(1.0f, 10).layers.size(), 0u);
    EXPECT_EQ(film.resolveCombined(1.0f).at(3, 4), Rgb(0.0f));
}

TEST(Film, ConcurrentAddOnDistinctTilesMatchesSerial) {
    // Non-dyadic values: each tile is filled by one thread in the serial order, so every pixel
    // sees the same sequence of adds and the results must be identical bit for bit.
    const int w = 100, h = 70;
    const auto samples = randomSamples(w, h, 100000, 5, /*dyadic=*/false);
    Film serial(w, h), parallel(w, h);
    addAll(serial, samples);
    addConcurrently(parallel, samples, 4);
    EXPECT_EQ(serial.typeCount(), parallel.typeCount());
    expectBytewiseEqual(serial.resolve(0.5f, 3), parallel.resolve(0.5f, 3));
}

TEST(Film, SharedAddsFromManyThreadsOnTheSameTilesMatchSerial) {
    // The MCMC chains' case: every thread adds anywhere, so threads meet in one tile (a small
    // film of 4 tiles, 8 threads, each taking every 8th sample in turn). The tile locks keep
    // the sums whole and the fixed-point sums make their order irrelevant: bit for bit the
    // serial film, with the same types in it.
    const int w = 32, h = 32, threads = 8;
    const auto samples = randomSamples(w, h, 200000, 17, /*dyadic=*/false);
    Film serial(w, h), shared(w, h);
    addAll(serial, samples);
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (size_t i = size_t(t); i < samples.size(); i += threads)
                shared.addSampleShared(samples[i].x, samples[i].y, samples[i].type,
                                       samples[i].value);
        });
    for (auto& th : pool) th.join();
    EXPECT_EQ(serial.typeCount(), shared.typeCount());
    expectBytewiseEqual(serial.resolve(0.5f, 8), shared.resolve(0.5f, 8));
    // A sample outside the film is ignored, as by addSample.
    shared.addSampleShared(-1, 3, someTypes()[0], Rgb(1.0f));
    shared.addSampleShared(w, 3, someTypes()[0], Rgb(1.0f));
    expectBytewiseEqual(serial.resolve(0.5f, 8), shared.resolve(0.5f, 8));
}

TEST(Film, ResolveOnAPoolEqualsSerialBitForBit) {
    // Non-dyadic values, edge tiles on both sides, an odd scale: spreading resolve over threads
    // must not change a single bit, for any number of kept layers ("other" sums many types).
    const int w = 83, h = 45;
    Film film(w, h);
    addAll(film, randomSamples(w, h, 60000, 11, /*dyadic=*/false));
    for (int threads : {1, 2, 4}) {
        ThreadPool pool(threads);
        for (int keep : {0, 1, 3, 100}) {
            SCOPED_TRACE(testing::Message() << threads << " threads, keep " << keep);
            for (float scale : {1.0f, 0.37f})
                expectBytewiseEqual(film.resolve(scale, keep), film.resolve(scale, keep, &pool));
        }
    }
    // An empty film and one smaller than a tile.
    ThreadPool pool(2);
    Film empty(0, 0), small(5, 3);
    small.addSample(4, 2, typeFromString("LDE"), Rgb(0.3f));
    expectBytewiseEqual(empty.resolve(1.0f, 2), empty.resolve(1.0f, 2, &pool));
    expectBytewiseEqual(small.resolve(0.5f, 2), small.resolve(0.5f, 2, &pool));
}

TEST(Film, MoveAndTypeCount) {
    Film film(20, 20);
    EXPECT_EQ(film.tilesX(), 2);
    EXPECT_EQ(film.tilesY(), 2);
    film.addSample(0, 0, typeFromString("LDE"), Rgb(1.0f));
    film.addSample(19, 19, typeFromString("LDE"), Rgb(1.0f));
    film.addSample(19, 0, typeFromString("LSDE"), Rgb(1.0f));
    film.addSample(2, 2, typeFromString("LSDE"), Rgb(0.0f));  // black: no effect
    film.addSample(-1, 0, typeFromString("LE"), Rgb(1.0f));   // outside: ignored
    film.addSample(0, 20, typeFromString("LE"), Rgb(1.0f));
    EXPECT_EQ(film.typeCount(), 2u);

    Film moved(std::move(film));
    EXPECT_EQ(moved.width(), 20);
    EXPECT_EQ(moved.typeCount(), 2u);
    Film assigned(1, 1);
    assigned = std::move(moved);
    EXPECT_EQ(assigned.resolveCombined(1.0f).at(19, 19), Rgb(1.0f));
}

// ---- Bounded type layers (issue #24): the film keeps the types it is given, "other" the rest.

/// Many distinct types (every string of 1..7 scattering vertices: 254), so that a bounded film
/// has far more types than layers.
std::vector<PathType> manyTypes() {
    std::vector<PathType> out;
    for (int n = 1; n <= 7; ++n)
        for (uint64_t mask = 0; mask < (uint64_t(1) << n); ++mask) {
            PathType t;
            EXPECT_TRUE(PathType::fromBits(mask, n, t));
            out.push_back(t);
        }
    return out;
}

std::vector<Sample> manyTypeSamples(int w, int h, size_t n, uint32_t seed) {
    std::mt19937 rng(seed);
    const auto types = manyTypes();
    std::uniform_int_distribution<int> dx(0, w - 1), dy(0, h - 1), dt(0, int(types.size()) - 1),
        dk(1, 1023);
    std::vector<Sample> out;
    for (size_t i = 0; i < n; ++i)
        out.push_back({dx(rng),
                       dy(rng),
                       types[size_t(dt(rng))],
                       {dk(rng) / 64.0f, dk(rng) / 64.0f, dk(rng) / 64.0f}});
    return out;
}

TEST(TypeLayers, LargestKeepsTheHeaviestTiesByTypeOrder) {
    const auto t = someTypes();  // LE LDE LSE LDDE LSDE ...
    std::map<PathType, double> w{{t[0], 1.0}, {t[1], 3.0}, {t[2], 3.0}, {t[3], 0.0}, {t[4], 2.0}};
    const TypeLayers two = TypeLayers::largest(w, 2);
    ASSERT_EQ(two.types().size(), 2u);
    // LDE and LSE tie at 3: both kept; LSDE (2) is not.
    EXPECT_TRUE(two.keeps(t[1]) && two.keeps(t[2]));
    EXPECT_FALSE(two.keeps(t[4]));
    // The tie for the last place goes to the smaller PathType.
    const TypeLayers one = TypeLayers::largest(w, 1);
    EXPECT_TRUE(one.keeps(std::min(t[1], t[2])));
    EXPECT_FALSE(one.keeps(std::max(t[1], t[2])));
    // A weight of zero never earns a layer; more room than types keeps them all.
    EXPECT_FALSE(TypeLayers::largest(w, 10).keeps(t[3]));
    EXPECT_EQ(TypeLayers::largest(w, 10).types().size(), 4u);
    EXPECT_TRUE(TypeLayers::largest(w, 0).keepsNone());
    EXPECT_TRUE(TypeLayers::every().keeps(t[3]));
    EXPECT_FALSE(TypeLayers::every().keepsNone());
}

TEST(Film, ATypeOutsideTheKeptSetLandsInOtherAndLayersSumToCombinedExactly) {
    const int w = 37, h = 21;
    const auto types = manyTypes();
    const TypeLayers kept = TypeLayers::of({types[0], types[5], types[40], types[200]});
    Film bounded(w, h, kept), every(w, h);
    const auto samples = manyTypeSamples(w, h, 20000, 5);
    addAll(bounded, samples);
    addAll(every, samples);

    const LayeredImage img = bounded.resolve(1.0f, 1024);
    ASSERT_EQ(img.layers.size(), 5u);  // the four kept types and "other"
    EXPECT_EQ(img.layers.back().name, Film::kOtherLayer);
    EXPECT_EQ(bounded.typeCount(), 4u);
    // Each kept layer is the type's own sums; "other" is everything else (the unbounded film's
    // other types); the values are dyadic with few per pixel, so float sums are exact.
    const LayeredImage all = every.resolve(1.0f, 1024);
    for (const auto& layer : img.layers) {
        if (layer.name == Film::kOtherLayer) continue;
        ASSERT_NE(all.layer(layer.name), nullptr) << layer.name;
        EXPECT_EQ(layer.image.rgb, all.layer(layer.name)->rgb) << layer.name;
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Rgb rest(0.0f), sum(0.0f);
            for (const auto& layer : all.layers) {
                PathType t;
                ASSERT_TRUE(PathType::parse(layer.name, t));
                if (!kept.keeps(t)) rest += layer.image.at(x, y);
            }
            for (const auto& layer : img.layers) sum += layer.image.at(x, y);
            EXPECT_EQ(img.layer(Film::kOtherLayer)->at(x, y), rest) << x << "," << y;
            EXPECT_EQ(sum, img.combined.at(x, y)) << x << "," << y;
            EXPECT_EQ(img.combined.at(x, y), all.combined.at(x, y));
        }
}

TEST(Film, ABoundedFilmHoldsAtMostItsLayersPlusTwoBuffersPerTile) {
    const int w = 64, h = 48;
    const auto types = manyTypes();
    const auto samples = manyTypeSamples(w, h, 100000, 6);
    for (size_t layers : {0u, 1u, 8u, 32u}) {
        SCOPED_TRACE(testing::Message() << layers << " layers");
        std::vector<PathType> chosen(types.begin(), types.begin() + long(layers));
        Film film(w, h, TypeLayers::of(chosen));
        addAll(film, samples);
        // Every tile saw (nearly) every one of the 254 types: unbounded, it would hold ~255.
        EXPECT_LE(film.maxBuffersPerTile(), layers == 0 ? 1 : layers + 2);
        EXPECT_GE(film.maxBuffersPerTile(), layers == 0 ? 1 : layers + 1);
    }
    Film every(w, h);
    addAll(every, samples);
    EXPECT_GT(every.maxBuffersPerTile(), 200u);  // the check above can fail
}

TEST(Film, AFilmKeepingNoTypeHasOnlyItsCombinedImage) {
    const int w = 20, h = 20;
    Film none(w, h, TypeLayers::of({})), every(w, h);
    const auto samples = manyTypeSamples(w, h, 3000, 7);
    addAll(none, samples);
    addAll(every, samples);
    const LayeredImage img = none.resolve(1.0f, 32);
    EXPECT_TRUE(img.layers.empty());
    EXPECT_EQ(img.combined.rgb, every.resolveCombined(1.0f).rgb);
    EXPECT_EQ(none.maxBuffersPerTile(), 1u);
}

TEST(Film, BoundedFilmsMergeAndSerializeExactlyAndRefuseOtherLayers) {
    const int w = 33, h = 17;
    const auto types = manyTypes();
    const TypeLayers kept = TypeLayers::of({types[3], types[100]});
    const auto samples = manyTypeSamples(w, h, 8000, 8);
    Film whole(w, h, kept), a(w, h, kept), b(w, h, kept);
    addAll(whole, samples);
    for (size_t i = 0; i < samples.size(); ++i) {
        const Sample& s = samples[i];
        (i % 3 == 0 ? a : b).addSample(s.x, s.y, s.type, s.value);
    }
    a.merge(b);
    EXPECT_EQ(a.serialize(), whole.serialize());
    const std::vector<uint8_t> bytes = whole.serialize();
    Film back = Film::deserialize(bytes);
    EXPECT_TRUE(back.layers() == kept);
    EXPECT_EQ(back.serialize(), bytes);
    expectBytewiseEqual(back.resolve(1.0f, 32), whole.resolve(1.0f, 32));

    Film unbounded(w, h), otherSet(w, h, TypeLayers::of({types[3]}));
    EXPECT_THROW(whole.merge(unbounded), std::invalid_argument);
    EXPECT_THROW(whole.merge(otherSet), std::invalid_argument);
}

TEST(Film, TakeResolvedEqualsResolveBitForBitAndEmptiesTheFilm) {
    const int w = 45, h = 29;
    const auto types = manyTypes();
    const auto samples = manyTypeSamples(w, h, 30000, 9);
    ThreadPool pool(3);
    for (const TypeLayers& layers :
         {TypeLayers::every(), TypeLayers::of({types[1], types[7], types[99]}),
          TypeLayers::of({})}) {
        for (int maxLayers : {0, 2, 1024}) {
            SCOPED_TRACE(testing::Message() << layers.types().size() << " kept, " << maxLayers);
            Film film(w, h, layers);
            // Arbitrary values: the same additions in the same order give the same bits.
            for (const Sample& s : samples) film.addSample(s.x, s.y, s.type, s.value * 0.37f);
            const LayeredImage expected = film.resolve(0.25f, maxLayers);
            const LayeredImage taken = film.takeResolved(0.25f, maxLayers, &pool);
            expectBytewiseEqual(taken, expected);
            EXPECT_EQ(film.typeCount(), 0u);
            EXPECT_EQ(film.resolveCombined(1.0f).rgb, Image(w, h).rgb);
            film.addSample(3, 4, types[1], Rgb(1.0f));  // still usable
            EXPECT_EQ(film.resolveCombined(1.0f).at(3, 4), Rgb(1.0f));
        }
    }
}

TEST(Film, ReleaseLeavesAnEmptyFilmThatTakesNoSample) {
    Film film(40, 20, TypeLayers::every());
    for (const Sample& s : manyTypeSamples(40, 20, 500, 3))
        film.addSample(s.x, s.y, s.type, s.value);
    ASSERT_GT(film.typeCount(), 0u);
    film.release();
    EXPECT_EQ(film.width(), 0);
    EXPECT_EQ(film.height(), 0);
    EXPECT_EQ(film.typeCount(), 0u);
    EXPECT_EQ(film.maxBuffersPerTile(), 0u);
    film.addSample(3, 4, manyTypes()[1], Rgb(1.0f));  // outside a 0x0 film: ignored
    EXPECT_TRUE(film.resolveCombined(1.0f).rgb.empty());
}

}  // namespace
}  // namespace partita
