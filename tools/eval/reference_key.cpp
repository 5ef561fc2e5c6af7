#include "eval/reference_key.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <stdexcept>

#include "gltf/gltf_io.h"
#include "gltf/resource_resolver.h"
#include "params/job_parameters.h"

namespace partita::eval {

namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> readFile(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("cannot read scene '" + path.string() + "'");
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

uint32_t readU32(const std::vector<uint8_t>& b, size_t at) {
    uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = v << 8 | b[at + size_t(i)];
    return v;
}

/// The JSON of a .gltf, or the JSON chunk of a .glb (header: magic, version, length; then the
/// first chunk: length, type "JSON", bytes). Empty when there is none to read.
std::string gltfJson(const std::vector<uint8_t>& bytes) {
    bool glb = bytes.size() >= 20 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    if (!glb) return {bytes.begin(), bytes.end()};
    uint32_t length = readU32(bytes, 12);
    if (std::memcmp(&bytes[16], "JSON", 4) != 0 || length > bytes.size() - 20) return {};
    return {bytes.begin() + 20, bytes.begin() + 20 + length};
}

/// The external uris of buffers and images, in file order, each once. A file that does not
/// parse names none (the loader rejects it later with a clear message).
std::vector<std::string> externalUris(const std::vector<uint8_t>& bytes) {
    nlohmann::json doc = nlohmann::json::parse(gltfJson(bytes), nullptr, false);
    std::vector<std::string> uris;
    if (!doc.is_object()) return uris;
    std::set<std::string> seen;
    for (const char* array : {"buffers", "images"}) {
        auto it = doc.find(array);
        if (it == doc.end() || !it->is_array()) continue;
        for (const auto& entry : *it) {
            if (!entry.is_object() || !entry.contains("uri") || !entry["uri"].is_string()) continue;
            std::string uri = entry["uri"].get<std::string>();
            if (uri.rfind("data:", 0) == 0 || !seen.insert(uri).second) continue;
            uris.push_back(uri);
        }
    }
    return uris;
}

/// The shortest text that reads back to exactly `v` (float and double alike).
template <class T>
std::string number(T v) {
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return {buf, r.ptr};
}

}  // namespace

std::string hashBytes(const void* bytes, size_t size) {
    // FNV-1a with the 128-bit parameters (offset basis and prime 2^88 + 0x13b).
    using u128 = unsigned __int128;
    u128 h = (u128(0x6c62272e07bb0142ull) << 64) | 0x62b821756295c58dull;
    const u128 prime = (u128(1) << 88) | 0x13b;
    const auto* p = static_cast<const uint8_t*>(bytes);
    for (size_t i = 0; i < size; ++i) h = (h ^ p[i]) * prime;
    char out[33];
    std::snprintf(out, sizeof out, "%016llx%016llx", (unsigned long long)(h >> 64),
                  (unsigned long long)h);
    return out;
}

std::vector<SceneFile> sceneFiles(const fs::path& scene) {
    std::vector<uint8_t> bytes = readFile(scene);
    std::vector<SceneFile> files{{"scene", bytes.size(), hashBytes(bytes.data(), bytes.size())}};
    FolderResolver folder(fs::absolute(scene).parent_path());
    for (const auto& uri : externalUris(bytes)) {
        std::string error;
        auto resource = folder.read(gltf::decodeUriLikeTinygltf(uri), error);
        if (resource)
            files.push_back({uri, resource->size(), hashBytes(resource->data(), resource->size())});
        else
            files.push_back({uri, 0, "missing"});
    }
    return files;
}

std::string referenceKeyText(const std::vector<SceneFile>& files, const std::string& algorithm,
                             const RenderSettings& s) {
    std::ostringstream t;
    t << "format=" << kReferenceFormat << "\n"
      << "algorithm=" << algorithm << "\n"
      << "budget_kind=" << budgetKindName(s.budgetKind) << "\nbudget=" << number(s.budget) << "\n";
    // Every declared parameter that changes the image, defaults filled in; the environment
    // file by its bytes (below), the preview interval not at all.
    for (const JobParameter& p : jobParameters(registeredAlgorithm(algorithm), s)) {
        const std::string& name = p.spec->name;
        if (name == "environment" || name == "preview_interval") continue;
        if (std::holds_alternative<std::monostate>(p.value)) continue;
        t << name << "=" << formatParameter(*p.spec, p.value) << "\n";
    }
    const EnvironmentSettings& env = s.environment;
    if (!env.file.empty()) {
        // The environment image by its bytes, as the scene's files.
        std::vector<uint8_t> bytes;
        std::error_code ec;
        if (fs::exists(env.file, ec)) bytes = readFile(env.file);
        t << "environment_file " << bytes.size() << " " << hashBytes(bytes.data(), bytes.size())
          << "\n";
    }
    for (const auto& f : files) t << "file " << f.name << " " << f.size << " " << f.hash << "\n";
    return t.str();
}

std::string referenceKey(const std::vector<SceneFile>& files, const std::string& algorithm,
                         const RenderSettings& settings) {
    std::string text = referenceKeyText(files, algorithm, settings);
    return hashBytes(text.data(), text.size());
}

}  // namespace partita::eval
