// A PathType in the binary files (films, shard plans): its specular mask and vertex count.
#pragma once

#include <cstdint>

#include "byte_stream.h"
#include "path_type.h"

namespace partita {

inline void putPathType(ByteWriter& w, const PathType& t) {
    w.put(t.specularMask());
    w.put(uint16_t(t.scatteringVertices()));
}

/// Fails the reader with "bad path type" for a count out of range or stray mask bits.
inline PathType getPathType(ByteReader& r) {
    const uint64_t mask = r.get<uint64_t>();
    const uint16_t count = r.get<uint16_t>();
    PathType t;
    if (!PathType::fromBits(mask, count, t)) r.fail("bad path type");
    return t;
}

}  // namespace partita
