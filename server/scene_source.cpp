#include "scene_source.h"

#include <algorithm>
#include <map>

#include "text.h"

namespace partita::server {

namespace fs = std::filesystem;

namespace {

bool isInside(const fs::path& path, const fs::path& root) {
    auto [r, p] = std::mismatch(root.begin(), root.end(), path.begin(), path.end());
    return r == root.end() && p != path.end();
}

std::vector<uint8_t> bytesOf(const std::string& s) {
    return std::vector<uint8_t>(s.begin(), s.end());
}

}  // namespace

SceneSource::SceneSource(const fs::path& root) {
    if (root.empty()) return;
    std::error_code ec;
    root_ = fs::canonical(root, ec);
    if (ec) root_ = fs::absolute(root, ec);
}

std::string SceneSource::checkName(const std::string& name) {
    if (name.empty()) return "the scene name is empty";
    if (name.size() > 200) return "the scene name is longer than 200 characters";
    for (unsigned char c : name)
        if (c < 0x20 || c == 0x7f) return "the scene name contains control characters";
    if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
        return "a scene name is one folder name under the scene root, without '/' or '\\'";
    if (name.front() == '.') return "a scene name may not start with '.'";
    if (name.find(':') != std::string::npos) return "a scene name may not contain ':'";
    return {};
}

fs::path SceneSource::find(const std::string& name, grpc::StatusCode& code,
                           std::string& error) const {
    if (std::string why = checkName(name); !why.empty()) {
        code = grpc::StatusCode::INVALID_ARGUMENT;
        error = "invalid scene name: " + why;
        return {};
    }
    if (root_.empty()) {
        code = grpc::StatusCode::NOT_FOUND;
        error = "no scene named '" + quoteInput(name) +
                "': this server has no scene root (--scene-root)";
        return {};
    }
    const fs::path candidates[] = {root_ / name / (name + ".gltf"), root_ / name / (name + ".glb"),
                                   root_ / (name + ".glb")};
    for (const fs::path& candidate : candidates) {
        std::error_code ec;
        if (!fs::exists(candidate, ec)) continue;
        // Canonical: every symlink on the way resolved, so a link out of the root is caught here.
        fs::path real = fs::canonical(candidate, ec);
        if (ec || !isInside(real, root_)) {
            code = grpc::StatusCode::INVALID_ARGUMENT;
            error = "scene '" + quoteInput(name) + "' resolves outside the scene root; refused";
            return {};
        }
        if (!fs::is_regular_file(real, ec)) continue;
        return real;
    }
    code = grpc::StatusCode::NOT_FOUND;
    error = "no scene named '" + quoteInput(name) + "' under the scene root";
    return {};
}

fs::path SceneSource::resolve(const std::string& name, grpc::StatusCode& code,
                              std::string& error) const {
    fs::path file = find(name, code, error);
    if (file.empty() && code == grpc::StatusCode::NOT_FOUND && !root_.empty()) {
        std::string names;
        for (const auto& e : list()) names += (names.empty() ? "" : ", ") + e.name;
        error += " (available: " + (names.empty() ? std::string("none") : names) + ")";
    }
    return file;
}

std::vector<SceneEntry> SceneSource::list() const {
    std::vector<SceneEntry> out;
    if (root_.empty()) return out;
    std::error_code ec;
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(root_, ec)) {
        std::string n = entry.path().filename().string();
        if (entry.path().extension() == ".glb") n = entry.path().stem().string();
        // A name that is not UTF-8 could not be asked for (requests are UTF-8): leave it out.
        if (isValidUtf8(n)) names.push_back(n);
    }
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    for (const auto& name : names) {
        grpc::StatusCode code;
        std::string error;
        fs::path file = find(name, code, error);
        if (file.empty()) continue;
        out.push_back({name, fs::relative(file, root_, ec).string()});
    }
    return out;
}

std::vector<uint8_t> SceneSource::readNamedResource(const std::string& name, const std::string& uri,
                                                    uint64_t maxBytes) const {
    grpc::StatusCode code;
    std::string error;
    fs::path file = resolve(name, code, error);
    if (file.empty()) throw SceneLoadError(error);
    FolderResolver folder(file.parent_path(), maxBytes);
    auto bytes = folder.read(uri, error);
    if (!bytes) throw SceneLoadError(error);
    return *bytes;
}

std::vector<uint8_t> SceneSource::readUploadedResource(const pb::SceneSource& upload,
                                                       const std::string& uri) {
    if (upload.source_case() == pb::SceneSource::kGltf)
        for (const auto& r : upload.gltf().resources())
            if (r.uri() == uri) return bytesOf(r.data());
    throw SceneLoadError("no resource '" + quoteInput(uri, 64) + "' was uploaded with the scene");
}

SceneData SceneSource::loadNamed(const std::string& name) const {
    grpc::StatusCode code;
    std::string error;
    fs::path file = resolve(name, code, error);
    if (file.empty()) throw SceneLoadError(error);
    return loadGltfFile(file);
}

uint64_t SceneSource::sceneBytes(const std::string& name) const {
    grpc::StatusCode code;
    std::string error;
    fs::path file = find(name, code, error);
    if (file.empty()) return 0;
    std::error_code ec;
    if (file.parent_path() == root_) return fs::file_size(file, ec);
    uint64_t total = 0;  // <root>/<name>/: the scene file and its resources beside it
    for (const auto& entry : fs::directory_iterator(file.parent_path(), ec))
        if (entry.is_regular_file(ec)) total += entry.file_size(ec);
    return total;
}

uint64_t SceneSource::uploadBytes(const pb::SceneSource& source) {
    switch (source.source_case()) {
        case pb::SceneSource::kGlb:
            return source.glb().size();
        case pb::SceneSource::kGltf: {
            uint64_t total = source.gltf().gltf().size();
            for (const auto& r : source.gltf().resources())
                total += r.data().size() + r.uri().size();
            return total;
        }
        default:
            return 0;
    }
}

SceneData SceneSource::loadUpload(const pb::SceneSource& upload, uint64_t maxBytes) {
    GltfLoadLimits limits;
    limits.maxFileBytes = maxBytes;
    if (upload.source_case() == pb::SceneSource::kGlb)
        return loadGltfMemory(bytesOf(upload.glb()), true, MemoryResolver({}), limits);
    if (upload.source_case() == pb::SceneSource::kGltf) {
        std::map<std::string, std::vector<uint8_t>> files;
        for (const auto& r : upload.gltf().resources()) files[r.uri()] = bytesOf(r.data());
        return loadGltfMemory(bytesOf(upload.gltf().gltf()), false,
                              MemoryResolver(std::move(files)), limits);
    }
    throw SceneLoadError("the job has no uploaded scene");
}

}  // namespace partita::server
