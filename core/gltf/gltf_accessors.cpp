#include "gltf/gltf_accessors.h"

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "gltf/gltf_common.h"

namespace partita::gltf {

namespace {

struct ByteSpan {
    const uint8_t* data = nullptr;
    uint64_t size = 0;
};

/// How one element is stored.
struct ElementFormat {
    int componentType = 0;
    int components = 0;
    bool normalized = false;
    uint64_t componentBytes = 0;
    uint64_t bytes() const { return componentBytes * uint64_t(components); }
};

/// Bytes per component for the componentTypes glTF 2.0 allows for accessors (not INT, DOUBLE).
uint64_t componentBytes(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

template <typename T>
T load(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));  // glTF data is little-endian and need not be aligned
    return v;
}

double decodeComponent(const uint8_t* p, const ElementFormat& f) {
    switch (f.componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            double v = load<int8_t>(p);
            return f.normalized ? std::max(v / 127.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
            double v = load<uint8_t>(p);
            return f.normalized ? v / 255.0 : v;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            double v = load<int16_t>(p);
            return f.normalized ? std::max(v / 32767.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            double v = load<uint16_t>(p);
            return f.normalized ? v / 65535.0 : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            double v = load<uint32_t>(p);
            return f.normalized ? v / 4294967295.0 : v;
        }
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
        default:
            return load<float>(p);
    }
}

template <typename T>
T convertComponent(double v) {
    if constexpr (std::is_same_v<T, float>)
        return toFloat(v);
    else
        return T(v);  // indices: exact non-negative integers below 2^32
}

template <typename T>
void decodeElement(const uint8_t* p, const ElementFormat& f, T* out) {
    for (int c = 0; c < f.components; ++c)
        out[c] = convertComponent<T>(decodeComponent(p + uint64_t(c) * f.componentBytes, f));
}

/// The bytes of bufferView `index`, checked against its buffer.
ByteSpan viewBytes(const LoadContext& ctx, int index, const std::string& what) {
    const tinygltf::BufferView& view = checkedAt(ctx.model.bufferViews, index, "bufferView");
    const tinygltf::Buffer& buffer = checkedAt(ctx.model.buffers, view.buffer, "buffer");
    uint64_t size = buffer.data.size();
    if (view.byteOffset > size || view.byteLength > size - view.byteOffset)
        failf("{}: bufferView {} (offset {}, length {}) is out of bounds of buffer {} ({} bytes)",
              what, index, view.byteOffset, view.byteLength, view.buffer, size);
    return {buffer.data.data() + view.byteOffset, view.byteLength};
}

/// Fails unless `count` elements of `elementBytes`, `stride` apart, starting at `offset`, lie in
/// a span of `size` bytes. In 64-bit math with stride <= 2^16 and count <= 2^40 (far above the
/// limits: strides are at most 252) the product cannot overflow.
void checkRange(uint64_t offset, uint64_t stride, uint64_t count, uint64_t elementBytes,
                uint64_t size, const std::string& what) {
    if (count == 0) return;
    bool fits = offset <= size && stride <= (uint64_t(1) << 16) && count <= (uint64_t(1) << 40) &&
                stride * (count - 1) + elementBytes <= size - offset;
    if (!fits)
        failf(
            "{}: {} elements at offset {} with stride {} reach past the end of their {}-byte "
            "bufferView",
            what, count, offset, stride, size);
}

template <typename T>
void applySparse(const LoadContext& ctx, const tinygltf::Accessor& acc, const ElementFormat& f,
                 std::vector<T>& values, const std::string& what) {
    const auto& sparse = acc.sparse;
    if (sparse.count < 1 || uint64_t(sparse.count) > acc.count)
        failf("{}: sparse count {} is outside 1..{}", what, sparse.count, acc.count);
    uint64_t count = uint64_t(sparse.count);

    ElementFormat indexFormat;
    indexFormat.componentType = sparse.indices.componentType;
    indexFormat.components = 1;
    indexFormat.componentBytes = componentBytes(indexFormat.componentType);
    if (indexFormat.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        indexFormat.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
        indexFormat.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        indexFormat.componentBytes == 0)
        failf("{}: sparse indices have invalid componentType {}", what, indexFormat.componentType);
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
        failf("{}: sparse byteOffset is negative", what);

    ByteSpan indexView = viewBytes(ctx, sparse.indices.bufferView, what + " sparse indices");
    ByteSpan valueView = viewBytes(ctx, sparse.values.bufferView, what + " sparse values");
    uint64_t indexOffset = uint64_t(sparse.indices.byteOffset);
    uint64_t valueOffset = uint64_t(sparse.values.byteOffset);
    checkRange(indexOffset, indexFormat.bytes(), count, indexFormat.bytes(), indexView.size,
               what + " sparse indices");
    checkRange(valueOffset, f.bytes(), count, f.bytes(), valueView.size, what + " sparse values");

    for (uint64_t j = 0; j < count; ++j) {
        double target =
            decodeComponent(indexView.data + indexOffset + j * indexFormat.bytes(), indexFormat);
        if (target >= double(acc.count))
            failf("{}: sparse index {} is out of range of the accessor's {} elements", what,
                  uint64_t(target), acc.count);
        decodeElement(valueView.data + valueOffset + j * f.bytes(), f,
                      &values[uint64_t(target) * uint64_t(f.components)]);
    }
}

/// An accessor with no bufferView is all zeros plus its sparse values. Its count costs memory
/// without costing file size, so it is capped (far above any real use) to stop a tiny file from
/// asking for gigabytes.
uint64_t maxZeroBaseCount(const tinygltf::Accessor& acc) {
    uint64_t sparse = acc.sparse.isSparse && acc.sparse.count > 0 ? uint64_t(acc.sparse.count) : 0;
    return std::max<uint64_t>(uint64_t(1) << 20, 64 * sparse);
}

void chargeDecodeBudget(LoadContext& ctx, uint64_t count, const std::string& where) {
    uint64_t budget =
        16 * std::min<uint64_t>(ctx.limits.maxTriangles, uint64_t(1) << 40) + (uint64_t(1) << 20);
    if (count > budget - std::min(budget, ctx.elementsDecoded))
        failf("{}: the file's accessors hold more than {} elements in all (the limit)", where,
              budget);
    ctx.elementsDecoded += count;
}

/// Decodes accessor `index` (checked to be of `type`) to `T` values, sparse applied.
template <typename T>
std::vector<T> readAccessor(LoadContext& ctx, int index, int type, uint64_t maxCount,
                            const std::string& what) {
    const tinygltf::Accessor& acc = checkedAt(ctx.model.accessors, index, "accessor");
    std::string where = what + " (accessor " + std::to_string(index) + ")";
    if (acc.type != type)
        failf("{}: has {} components per element, expected {}", where, componentsOf(acc.type),
              componentsOf(type));
    ElementFormat f;
    f.componentType = acc.componentType;
    f.components = componentsOf(type);
    f.normalized = acc.normalized;
    f.componentBytes = componentBytes(acc.componentType);
    if (f.componentBytes == 0) failf("{}: invalid componentType {}", where, acc.componentType);
    if (acc.count == 0) failf("{}: count is 0", where);
    if (acc.count > maxCount)
        failf("{}: count {} exceeds the limit of {}", where, acc.count, maxCount);

    // Everything is checked before the output is allocated.
    ByteSpan view;
    uint64_t stride = f.bytes();
    bool hasView = acc.bufferView != -1;
    if (hasView) {
        view = viewBytes(ctx, acc.bufferView, where);
        uint64_t viewStride = ctx.model.bufferViews[size_t(acc.bufferView)].byteStride;
        if (viewStride) stride = viewStride;
        checkRange(acc.byteOffset, stride, acc.count, f.bytes(), view.size, where);
    } else if (acc.count > maxZeroBaseCount(acc)) {
        failf("{}: count {} without a bufferView is implausibly large", where, acc.count);
    }
    chargeDecodeBudget(ctx, acc.count, where);
    std::vector<T> values(acc.count * size_t(f.components), T(0));
    if (hasView)
        for (uint64_t i = 0; i < acc.count; ++i)
            decodeElement(view.data + acc.byteOffset + i * stride, f,
                          &values[i * uint64_t(f.components)]);
    // With no bufferView the base is all zeros (glTF 2.0, 3.6.2.3), usually filled in by sparse.
    if (acc.sparse.isSparse) applySparse(ctx, acc, f, values, where);
    return values;
}

}  // namespace

int componentsOf(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        case TINYGLTF_TYPE_MAT2:
            return 4;
        case TINYGLTF_TYPE_MAT3:
            return 9;
        case TINYGLTF_TYPE_MAT4:
            return 16;
        default:
            return 0;
    }
}

std::vector<float> readFloatAccessor(LoadContext& ctx, int accessor, int type, uint64_t maxCount,
                                     const std::string& what) {
    return readAccessor<float>(ctx, accessor, type, maxCount, what);
}

std::vector<uint32_t> readIndexAccessor(LoadContext& ctx, int accessor, uint64_t maxCount,
                                        const std::string& what) {
    const tinygltf::Accessor& acc = checkedAt(ctx.model.accessors, accessor, "accessor");
    int ct = acc.componentType;
    if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        failf("{} (accessor {}): index componentType {} is not an unsigned byte, short or int",
              what, accessor, ct);
    if (acc.normalized) failf("{} (accessor {}): indices must not be normalized", what, accessor);
    return readAccessor<uint32_t>(ctx, accessor, TINYGLTF_TYPE_SCALAR, maxCount, what);
}

}  // namespace partita::gltf
