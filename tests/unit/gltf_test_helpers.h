// Builders for glTF test files: JSON documents with nlohmann::json, their binary data embedded as
// a base64 data: URI, written as an external .bin, or packed into a GLB; minimal PNG encoding;
// temporary folders. Test-only; shared by tests/unit/gltf/*_test.cpp.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gltf/gltf_loader.h"
#include "gltf/resource_resolver.h"

namespace partita::gltftest {

using nlohmann::json;

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125,
              kFloat = 5126;

inline std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t n = bytes.size();
    for (size_t i = 0; i < n; i += 3) {
        uint32_t chunk = uint32_t(bytes[i]) << 16 | (i + 1 < n ? uint32_t(bytes[i + 1]) << 8 : 0u) |
                         (i + 2 < n ? uint32_t(bytes[i + 2]) : 0u);
        out += kAlphabet[(chunk >> 18) & 63];
        out += kAlphabet[(chunk >> 12) & 63];
        out += n - i > 1 ? kAlphabet[(chunk >> 6) & 63] : '=';
        out += n - i > 2 ? kAlphabet[chunk & 63] : '=';
    }
    return out;
}

inline std::string dataUri(const std::vector<uint8_t>& bytes,
                           const std::string& mime = "application/octet-stream") {
    return "data:" + mime + ";base64," + base64(bytes);
}

template <typename T>
std::vector<uint8_t> bytesOf(const std::vector<T>& values) {
    std::vector<uint8_t> out(values.size() * sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), values.data(), out.size());
    return out;
}

/// A GLB container: a JSON chunk and, when `bin` is not empty, a BIN chunk (both padded).
inline std::vector<uint8_t> makeGlb(const std::string& jsonText, const std::vector<uint8_t>& bin) {
    size_t jsonLength = (jsonText.size() + 3) / 4 * 4, binLength = (bin.size() + 3) / 4 * 4;
    size_t total = 20 + jsonLength + (bin.empty() ? 0 : 8 + binLength);
    std::vector<uint8_t> out(total, 0);
    auto put32 = [&](size_t at, uint32_t v) {
        for (size_t k = 0; k < 4; ++k) out[at + k] = uint8_t(v >> (8 * k));
    };
    put32(0, 0x46546C67);  // "glTF"
    put32(4, 2);
    put32(8, uint32_t(total));
    put32(12, uint32_t(jsonLength));
    put32(16, 0x4E4F534A);
    for (size_t i = 0; i < jsonLength; ++i)
        out[20 + i] = i < jsonText.size() ? uint8_t(jsonText[i]) : ' ';
    if (!bin.empty()) {
        put32(20 + jsonLength, uint32_t(binLength));
        put32(24 + jsonLength, 0x004E4942);
        for (size_t i = 0; i < bin.size(); ++i) out[28 + jsonLength + i] = bin[i];
    }
    return out;
}

/// Accumulates one binary buffer and the JSON that describes it.
class GltfBuilder {
  public:
    GltfBuilder() {
        doc = {{"asset", {{"version", "2.0"}}}};
        doc["buffers"] = json::array();
        doc["bufferViews"] = json::array();
        doc["accessors"] = json::array();
        doc["meshes"] = json::array();
        doc["nodes"] = json::array();
    }

    /// A bufferView over `data` (appended, 4-byte aligned).
    int view(const std::vector<uint8_t>& data, int stride = 0) {
        while (bin.size() % 4) bin.push_back(0);
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", data.size()}};
        if (stride) v["byteStride"] = stride;
        bin.insert(bin.end(), data.begin(), data.end());
        doc["bufferViews"].push_back(v);
        return int(doc["bufferViews"].size()) - 1;
    }

    int accessor(int view, int componentType, size_t count, const std::string& type,
                 bool normalized = false, size_t byteOffset = 0) {
        json a = {{"componentType", componentType}, {"count", count}, {"type", type}};
        if (view >= 0) a["bufferView"] = view;
        if (normalized) a["normalized"] = true;
        if (byteOffset) a["byteOffset"] = byteOffset;
        doc["accessors"].push_back(a);
        return int(doc["accessors"].size()) - 1;
    }

    int floats(const std::vector<float>& values, const std::string& type) {
        size_t n = type == "SCALAR" ? 1 : size_t(type[3] - '0');
        return accessor(view(bytesOf(values)), kFloat, values.size() / n, type);
    }

    template <typename T>
    int indices(const std::vector<T>& values) {
        int ct = sizeof(T) == 1 ? kUByte : sizeof(T) == 2 ? kUShort : kUInt;
        return accessor(view(bytesOf(values)), ct, values.size(), "SCALAR");
    }

    int mesh(const json& primitives) {
        doc["meshes"].push_back({{"primitives", primitives}});
        return int(doc["meshes"].size()) - 1;
    }

    int node(const json& n) {
        doc["nodes"].push_back(n);
        return int(doc["nodes"].size()) - 1;
    }

    /// A scene of `roots` (default scene).
    void scene(const std::vector<int>& roots) {
        doc["scenes"] = json::array({{{"nodes", roots}}});
        doc["scene"] = 0;
    }

    /// The document with the buffer embedded as a data: URI.
    json embedded() const {
        json d = doc;
        if (!bin.empty())
            d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", dataUri(bin)}}});
        return d;
    }

    /// The document with the buffer as external file `uri`.
    json external(const std::string& uri) const {
        json d = doc;
        d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
        return d;
    }

    /// A GLB holding the document and the buffer.
    std::vector<uint8_t> glb() const {
        json d = doc;
        d["buffers"] = json::array({{{"byteLength", bin.size()}}});
        return makeGlb(d.dump(), bin);
    }

    json doc;
    std::vector<uint8_t> bin;
};

/// A unit quad in the z = 0 plane facing +Z: 4 vertices, 2 indexed triangles.
inline json quadPrimitive(GltfBuilder& b, bool withNormals = false, bool withUv = false) {
    json attrs = {{"POSITION", b.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3")}};
    if (withNormals) attrs["NORMAL"] = b.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
    if (withUv) attrs["TEXCOORD_0"] = b.floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2");
    return {{"attributes", attrs}, {"indices", b.indices<uint16_t>({0, 1, 2, 0, 2, 3})}};
}

/// A builder holding one node with the quad.
inline GltfBuilder quadScene(const json& nodeExtras = json::object()) {
    GltfBuilder b;
    int mesh = b.mesh(json::array({quadPrimitive(b, true, true)}));
    json n = {{"mesh", mesh}};
    n.update(nodeExtras);
    b.scene({b.node(n)});
    return b;
}

inline std::vector<uint8_t> textBytes(const std::string& s) { return {s.begin(), s.end()}; }

inline SceneData loadJson(const json& doc, std::map<std::string, std::vector<uint8_t>> files = {},
                          const GltfLoadLimits& limits = {}) {
    return loadGltfMemory(textBytes(doc.dump()), false, MemoryResolver(std::move(files)), limits);
}

/// The SceneLoadError message of `load()`, or a test failure when it does not throw.
template <typename F>
std::string errorOf(F&& load) {
    try {
        load();
    } catch (const SceneLoadError& e) {
        std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << "multi-line error: " << message;
        return message;
    }
    ADD_FAILURE() << "expected a SceneLoadError";
    return {};
}

inline std::string jsonError(const json& doc,
                             std::map<std::string, std::vector<uint8_t>> files = {},
                             const GltfLoadLimits& limits = {}) {
    return errorOf([&] { loadJson(doc, std::move(files), limits); });
}

// ---- PNG encoding (stored deflate blocks: no compression needed for tests) ----

inline uint32_t crc32(const uint8_t* data, size_t n, uint32_t crc = 0) {
    crc = ~crc;
    for (size_t i = 0; i < n; ++i) {
        crc ^= data[i];
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

/// PNG of `width` x `height` with `channels` (1..4) 8- or 16-bit samples (16-bit given as
/// host-order uint16 values in `samples`; 8-bit values must be < 256).
inline std::vector<uint8_t> makePng(int width, int height, int channels,
                                    const std::vector<uint16_t>& samples, int bitDepth = 8) {
    static const uint8_t kColorType[5] = {0, 0, 4, 2, 6};
    std::vector<uint8_t> raw;
    for (int y = 0; y < height; ++y) {
        raw.push_back(0);  // filter: none
        for (int x = 0; x < width * channels; ++x) {
            uint16_t v = samples[size_t(y) * size_t(width * channels) + size_t(x)];
            if (bitDepth == 16) raw.push_back(uint8_t(v >> 8));
            raw.push_back(uint8_t(v));
        }
    }
    std::vector<uint8_t> z = {0x78, 0x01};
    for (size_t i = 0; i < raw.size(); i += 65535) {
        size_t n = std::min<size_t>(65535, raw.size() - i);
        z.push_back(i + n >= raw.size() ? 1 : 0);
        z.insert(z.end(), {uint8_t(n), uint8_t(n >> 8), uint8_t(~n), uint8_t(~n >> 8)});
        z.insert(z.end(), raw.begin() + long(i), raw.begin() + long(i + n));
    }
    uint32_t a = 1, b = 0;
    for (uint8_t c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
    for (int k = 3; k >= 0; --k) z.push_back(uint8_t(((b << 16) | a) >> (8 * k)));

    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
    auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
        for (int k = 3; k >= 0; --k) png.push_back(uint8_t(data.size() >> (8 * k)));
        std::vector<uint8_t> body(type, type + 4);
        body.insert(body.end(), data.begin(), data.end());
        png.insert(png.end(), body.begin(), body.end());
        uint32_t crc = crc32(body.data(), body.size());
        for (int k = 3; k >= 0; --k) png.push_back(uint8_t(crc >> (8 * k)));
    };
    std::vector<uint8_t> ihdr;
    for (int v : {width, height})
        for (int k = 3; k >= 0; --k) ihdr.push_back(uint8_t(uint32_t(v) >> (8 * k)));
    ihdr.insert(ihdr.end(), {uint8_t(bitDepth), kColorType[channels], 0, 0, 0});
    chunk("IHDR", ihdr);
    chunk("IDAT", z);
    chunk("IEND", {});
    return png;
}

// ---- temporary folders ----

class TempDir {
  public:
    TempDir() {
        char pattern[] = "/tmp/partita-gltf-XXXXXX";
        char* made = mkdtemp(pattern);
        EXPECT_NE(made, nullptr);
        path_ = made ? made : "/tmp";
    }
    ~TempDir() {
        std::error_code ec;
        if (path_ != "/tmp") std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path write(const std::string& name, const std::vector<uint8_t>& bytes) const {
        std::filesystem::path p = path_ / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary)
            .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        return p;
    }

  private:
    std::filesystem::path path_;
};

}  // namespace partita::gltftest
