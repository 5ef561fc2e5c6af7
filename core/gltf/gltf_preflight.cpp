#include "gltf/gltf_preflight.h"

#include <cstring>
#include <nlohmann/json.hpp>

#include "gltf/gltf_common.h"
#include "gltf/gltf_extensions.h"

namespace partita::gltf {

namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;   // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
constexpr uint64_t kHeaderBytes = 12, kChunkHeaderBytes = 8;

uint32_t readLe32(const std::vector<uint8_t>& bytes, uint64_t offset) {
    return uint32_t(bytes[offset]) | uint32_t(bytes[offset + 1]) << 8 |
           uint32_t(bytes[offset + 2]) << 16 | uint32_t(bytes[offset + 3]) << 24;
}

bool isBase64Char(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' ||
           c == '/';
}

/// Bytes that tinygltf's base64 decoder yields: it stops at the first character outside the
/// alphabet (such as '=' padding).
uint64_t decodedBase64Size(std::string_view payload) {
    uint64_t n = 0;
    while (n < payload.size() && isBase64Char(payload[n])) ++n;
    return n / 4 * 3 + (n % 4 > 1 ? n % 4 - 1 : 0);
}

/// tinygltf reports a data: buffer whose size differs from byteLength by quoting the whole uri;
/// say what is wrong instead.
void checkDataUriBuffers(const nlohmann::json& root) {
    auto buffers = root.find("buffers");
    if (buffers == root.end() || !buffers->is_array()) return;
    for (size_t i = 0; i < buffers->size(); ++i) {
        const nlohmann::json& buffer = (*buffers)[i];
        if (!buffer.is_object()) continue;
        auto uri = buffer.find("uri");
        auto byteLength = buffer.find("byteLength");
        if (uri == buffer.end() || !uri->is_string() || byteLength == buffer.end() ||
            !byteLength->is_number_unsigned())
            continue;
        const std::string& text = uri->get_ref<const std::string&>();
        size_t comma = text.find(";base64,");
        if (text.rfind("data:", 0) != 0 || comma == std::string::npos) continue;
        uint64_t size = decodedBase64Size(std::string_view(text).substr(comma + 8));
        uint64_t declared = byteLength->get<uint64_t>();
        if (size != declared)
            failf("buffer {}: its data: URI holds {} bytes but byteLength is {}", i, size,
                  declared);
    }
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
    if (v.rfind("2.", 0) != 0)
        failf("glTF version {} is not supported (expected 2.x)", printableUri(v));

    checkDataUriBuffers(root);

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
