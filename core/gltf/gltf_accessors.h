// Typed, bounds-checked reading of glTF accessors: every componentType, the `normalized` flag,
// byteStride / byteOffset, and sparse substitution (which tinygltf 2.7 does not apply), also on
// an accessor with no bufferView (a zero base).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace partita::gltf {

struct LoadContext;

/// The accessor's elements as floats, `components(type)` per element, count * components in all.
/// Normalised integers map to [0, 1] / [-1, 1]; other integers convert to their value.
/// Fails when the accessor is not of `type` (TINYGLTF_TYPE_*), has more than `maxCount`
/// elements, or reaches outside its bufferView or buffer. `what` names the use in messages.
/// All reads of one load share a budget of 16 elements per allowed triangle (a primitive needs at
/// most ~15: positions, normals, two uv sets and indices), so that many primitives naming the
/// same large accessor cannot multiply the work.
std::vector<float> readFloatAccessor(LoadContext& ctx, int accessor, int type, uint64_t maxCount,
                                     const std::string& what);

/// A SCALAR accessor of unsigned byte / short / int (vertex indices).
std::vector<uint32_t> readIndexAccessor(LoadContext& ctx, int accessor, uint64_t maxCount,
                                        const std::string& what);

/// Number of components of a TINYGLTF_TYPE_* value, 0 when unknown.
int componentsOf(int type);

}  // namespace partita::gltf
