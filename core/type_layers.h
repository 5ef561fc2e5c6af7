// Which path types a film keeps a layer of (issue #24, "bounded type layers").
//
// A scene can produce thousands of Heckbert strings (bathroom: ~9300), and a film that kept a
// buffer for every one of them grew with the scene and the samples (a 720p bdpt render needed
// ~8 GB). A film is therefore given, before it renders anything, the set of types it keeps
// apart; every other type is summed into one "other" buffer. The set is chosen before the main
// render by a deterministic rule (layer_survey.h: the largest types of a short survey for pt and
// bdpt, of the bootstrap for the MCMC algorithms), so it does not depend on the thread count and
// every shard of a job uses the same one.
//
// `every()` keeps a layer for every type that occurs: the unbounded film, for tests and tools
// that compare estimators type by type on tiny images.
//
// A TypeLayers is cheap to copy (its table is shared, read-only) and compared by value.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "path_type.h"

namespace partita {

class ByteReader;
class ByteWriter;

class TypeLayers {
  public:
    /// Every type that occurs gets its own layer.
    static TypeLayers every();
    /// Exactly these types (sorted, duplicates removed); none: the combined image only.
    static TypeLayers of(std::vector<PathType> types);
    /// The `count` types of largest weight (weights <= 0 never count), ties broken by PathType
    /// order, so the choice is a function of the weights alone.
    static TypeLayers largest(const std::map<PathType, double>& weights, int count);

    bool keepsEvery() const { return !table_; }
    /// of({}): no type has a layer (a film then keeps its combined image only).
    bool keepsNone() const;
    /// Whether `type` has a layer of its own (always, for every()).
    bool keeps(PathType type) const;
    /// The kept types in PathType order (empty for every()).
    const std::vector<PathType>& types() const;

    void serialize(ByteWriter& w) const;
    /// Fails the reader on anything but serialize's bytes (bad or unsorted types).
    static TypeLayers deserialize(ByteReader& r);

    friend bool operator==(const TypeLayers& a, const TypeLayers& b);

  private:
    struct Table;
    explicit TypeLayers(std::shared_ptr<const Table> table) : table_(std::move(table)) {}
    std::shared_ptr<const Table> table_;  // null: every type
};

}  // namespace partita
