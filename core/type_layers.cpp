#include "type_layers.h"

#include <algorithm>
#include <bit>

#include "byte_stream.h"
#include "path_type_bytes.h"

namespace partita {

// The kept types in order, and an open-addressed table over them for keeps(), which the film
// asks on every sample whose type missed its per-tile cache.
struct TypeLayers::Table {
    std::vector<PathType> types;
    std::vector<uint32_t> slots;  // 0: empty, else index into types + 1
    int shift = 64;               // 64 - log2(slots.size())

    explicit Table(std::vector<PathType> sorted) : types(std::move(sorted)) {
        size_t size = 16;
        while (size < 4 * types.size()) size *= 2;
        slots.assign(size, 0);
        shift = 64 - std::countr_zero(size);
        for (size_t i = 0; i < types.size(); ++i) {
            size_t s = slotOf(types[i]);
            while (slots[s] != 0) s = (s + 1) & (slots.size() - 1);
            slots[s] = uint32_t(i + 1);
        }
    }
    size_t slotOf(PathType type) const {
        // Fibonacci hashing of both fields; the high bits of the product index the table.
        uint64_t h = (type.specularMask() ^ uint64_t(type.scatteringVertices()) << 57) *
                     0x9e3779b97f4a7c15ull;
        return size_t(h >> shift);
    }
    bool contains(PathType type) const {
        for (size_t s = slotOf(type);; s = (s + 1) & (slots.size() - 1)) {
            uint32_t e = slots[s];
            if (e == 0) return false;
            if (types[e - 1] == type) return true;
        }
    }
};

TypeLayers TypeLayers::every() { return TypeLayers(nullptr); }

TypeLayers TypeLayers::of(std::vector<PathType> types) {
    std::sort(types.begin(), types.end());
    types.erase(std::unique(types.begin(), types.end()), types.end());
    return TypeLayers(std::make_shared<const Table>(std::move(types)));
}

TypeLayers TypeLayers::largest(const std::map<PathType, double>& weights, int count) {
    std::vector<std::pair<PathType, double>> ranked;
    for (const auto& [type, weight] : weights)
        if (weight > 0) ranked.emplace_back(type, weight);
    // Stable over the map's PathType order: equal weights stay in type order.
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    ranked.resize(std::min(ranked.size(), size_t(std::max(0, count))));
    std::vector<PathType> kept;
    for (const auto& entry : ranked) kept.push_back(entry.first);
    return of(std::move(kept));
}

bool TypeLayers::keepsNone() const { return table_ && table_->types.empty(); }

bool TypeLayers::keeps(PathType type) const { return !table_ || table_->contains(type); }

const std::vector<PathType>& TypeLayers::types() const {
    static const std::vector<PathType> none;
    return table_ ? table_->types : none;
}

void TypeLayers::serialize(ByteWriter& w) const {
    w.put(uint8_t(keepsEvery() ? 1 : 0));
    w.put(uint32_t(types().size()));
    for (const PathType& t : types()) putPathType(w, t);
}

TypeLayers TypeLayers::deserialize(ByteReader& r) {
    const uint8_t every = r.get<uint8_t>();
    if (every > 1) r.fail("bad type layers");
    const uint32_t count = r.get<uint32_t>();
    if (every && count != 0) r.fail("bad type layers");
    if (every) return TypeLayers::every();
    std::vector<PathType> types;
    for (uint32_t i = 0; i < count; ++i) {
        types.push_back(getPathType(r));
        if (i > 0 && !(types[i - 1] < types[i])) r.fail("type layers out of order");
    }
    return of(std::move(types));
}

bool operator==(const TypeLayers& a, const TypeLayers& b) {
    return a.keepsEvery() == b.keepsEvery() && a.types() == b.types();
}

}  // namespace partita
