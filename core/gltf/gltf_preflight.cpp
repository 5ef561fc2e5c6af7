#include "gltf/gltf_preflight.h"

#include <cstring>
#include <nlohmann/json.hpp>

#include "gltf/gltf_common.h"
#include "gltf/gltf_extensions.h"

namespace partita::gltf {

namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;     // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;    // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;     // "BIN\0"
constexpr uint64_t kHeaderBytes = 12, kChunkHeaderBytes = 8;

uint32_t readLe32(const std::vector<uint8_t>& bytes, uint64_t offset) {
    return uint32_t(bytes[offset]) | uint32_t(bytes[offset + 1]) << 8 |
           uint32_t(bytes[offset + 2]) << 16 | uint32_t(bytes[offset + 3]) << 24;
}

}  // namespace

GlbLayout validateGlb(const std::vector<uint8_t>& bytes) {
    if (bytes.size() < kHeaderBytes + kChunkHeaderBytes)
        failf("GLB is truncated: {} bytes, less than the 20-byte header", bytes.size());
    if (readLe32(bytes, 0) != kGlbMagic) fail("GLB has a bad magic number (expected 'glTF')");
    uint32_t version = readLe32(bytes, 4);
    if (version != 2) failf("GLB container version {} is not supported (expected 2)", version);
    uint64_t length = readLe32(bytes, 8);
    if (length > bytes.size())
        failf("GLB is truncated: the header declares {} bytes but only {} are present", length,
              bytes.size());
    uint64_t jsonLength = readLe32(bytes, 12);
    if (readLe32(bytes, 16) != kChunkJson) fail("GLB's first chunk is not a JSON chunk");
    uint64_t jsonEnd = kHeaderBytes + kChunkHeaderBytes + jsonLength;
    if (jsonLength == 0 || jsonEnd > length)
        failf("GLB JSON chunk of {} bytes does not fit in the declared length of {} bytes",
              jsonLength, length);
    if (jsonEnd < length) {
        if (length - jsonEnd < kChunkHeaderBytes) fail("GLB is truncated inside a chunk header");
        uint64_t binLength = readLe32(bytes, jsonEnd);
        if (readLe32(bytes, jsonEnd + 4) == kChunkBin &&
            jsonEnd + kChunkHeaderBytes + binLength > length)
            failf("GLB BIN chunk of {} bytes runs past the end of the file", binLength);
    }
    GlbLayout layout;
    layout.length = uint32_t(length);
    layout.json = std::string_view(reinterpret_cast<const char*>(bytes.data()) + 20, jsonLength);
    return layout;
}

void checkJsonNesting(std::string_view json, int maxDepth) {
    int depth = 0;
    bool inString = false;
    for (size_t i = 0; i < json.size(); ++i) {
        char c = json[i];
        if (inString) {
            if (c == '\\')
                ++i;  // skip the escaped character
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > maxDepth) failf("JSON nests deeper than {} levels", maxDepth);
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

void checkGltfJson(std::string_view json) {
    nlohmann::json root;
    try {
        root = nlohmann::json::parse(json.begin(), json.end());
    } catch (const nlohmann::json::exception& e) {
        failf("invalid JSON: {}", e.what());
    }
    if (!root.is_object()) fail("glTF JSON root is not an object");
    auto asset = root.find("asset");
    if (asset == root.end() || !asset->is_object()) fail("glTF has no \"asset\" object");
    auto version = asset->find("version");
    if (version == asset->end() || !version->is_string())
        fail("glTF asset has no \"version\" string");
    const std::string& v = version->get_ref<const std::string&>();
    if (v.rfind("2.", 0) != 0) failf("glTF version {} is not supported (expected 2.x)", printableUri(v));

    auto required = root.find("extensionsRequired");
    if (required == root.end()) return;
    if (!required->is_array()) fail("glTF \"extensionsRequired\" is not an array");
    std::vector<std::string> names;
    for (const auto& name : *required) {
        if (!name.is_string()) fail("glTF \"extensionsRequired\" holds a non-string entry");
        names.push_back(name.get<std::string>());
    }
    checkRequiredExtensions(names);
}

}  // namespace partita::gltf
