#include "cli/scene_source.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <set>
#include <system_error>

#include "cli/errors.h"
#include "cli/file_util.h"

namespace partita::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool isDataUri(const std::string& uri) { return lower(uri.substr(0, 5)) == "data:"; }

/// Every uri of buffers and images that is not a data: URI, in file order, without repeats.
std::vector<std::string> externalUris(const json& doc) {
    std::vector<std::string> out;
    std::set<std::string> seen;
    for (const char* key : {"buffers", "images"}) {
        auto it = doc.find(key);
        if (it == doc.end() || !it->is_array()) continue;
        for (const auto& item : *it) {
            if (!item.is_object()) continue;
            auto uri = item.find("uri");
            if (uri == item.end() || !uri->is_string()) continue;
            std::string u = uri->get<std::string>();
            if (isDataUri(u) || !seen.insert(u).second) continue;
            out.push_back(u);
        }
    }
    return out;
}

/// The file a relative uri names inside `folder`; throws when it leads elsewhere.
fs::path resolveUri(const fs::path& sceneFile, const fs::path& folder, const std::string& uri) {
    auto refuse = [&](const std::string& why) -> fs::path {
        throw CliError("scene '" + sceneFile.string() + "' names resource '" + uri + "', which " +
                       why);
    };
    if (uri.empty()) refuse("is empty");
    // A scheme ("http:", "file:") before the first '/'.
    size_t colon = uri.find(':'), slash = uri.find('/');
    if (colon != std::string::npos && (slash == std::string::npos || colon < slash))
        refuse("is not a relative file name");
    const std::string decoded = percentDecode(uri);
    if (decoded.find('\0') != std::string::npos) refuse("contains a NUL byte");
    fs::path rel = fs::path(decoded).lexically_normal();
    if (rel.is_absolute() || decoded.front() == '/' || decoded.front() == '\\')
        refuse("is an absolute path");
    if (!rel.empty() && *rel.begin() == "..") refuse("lies outside the scene's folder");
    std::error_code ec;
    const fs::path base = fs::weakly_canonical(folder, ec);
    const fs::path target = fs::weakly_canonical(folder / rel, ec);
    if (ec) refuse("cannot be resolved");
    auto b = base.begin(), t = target.begin();
    for (; b != base.end(); ++b, ++t)
        if (t == target.end() || *b != *t) refuse("lies outside the scene's folder (symlink)");
    if (!fs::is_regular_file(target, ec)) refuse("does not exist or is not a file");
    return target;
}

void checkGlbHasNoExternalFiles(const fs::path& path, const std::string& bytes) {
    // 12-byte header, then the JSON chunk: length, type "JSON", data.
    if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0)
        throw CliError("'" + path.string() + "' is not a binary glTF file (bad header)");
    uint32_t length = 0, type = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    std::memcpy(&type, bytes.data() + 16, 4);
    if (type != 0x4E4F534Au || size_t(length) > bytes.size() - 20)
        throw CliError("'" + path.string() + "' is not a binary glTF file (no JSON chunk)");
    json doc = json::parse(bytes.begin() + 20, bytes.begin() + 20 + length, nullptr, false);
    if (doc.is_discarded() || !doc.is_object())
        throw CliError("'" + path.string() + "' has an unreadable JSON chunk");
    auto uris = externalUris(doc);
    if (!uris.empty())
        throw CliError("'" + path.string() + "' references the external file '" + uris.front() +
                       "'; a .glb is uploaded alone: embed its resources or use .gltf");
}

}  // namespace

std::string percentDecode(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] != '%') {
            out += uri[i];
            continue;
        }
        auto hex = [&](char c) -> int {
            if (c >= '0' && c <= '9') return c - '0';
            if (c >= 'a' && c <= 'f') return c - 'a' + 10;
            if (c >= 'A' && c <= 'F') return c - 'A' + 10;
            return -1;
        };
        if (i + 2 >= uri.size()) throw CliError("malformed %-escape in uri '" + uri + "'");
        int hi = hex(uri[i + 1]), lo = hex(uri[i + 2]);
        if (hi < 0 || lo < 0) throw CliError("malformed %-escape in uri '" + uri + "'");
        out += char(hi * 16 + lo);
        i += 2;
    }
    return out;
}

SceneArgument classifyScene(const std::string& scene) {
    SceneArgument arg;
    arg.text = scene;
    const std::string ext = lower(fs::path(scene).extension().string());
    std::error_code ec;
    arg.isFile = ext == ".gltf" || ext == ".glb" || fs::is_regular_file(scene, ec);
    return arg;
}

std::string sceneStem(const SceneArgument& scene) {
    if (scene.isFile) return fs::path(scene.text).stem().string();
    std::string s = fs::path(scene.text).filename().string();
    return s.empty() ? "scene" : s;
}

void addEnvironmentImage(partita::v1::JobSpec& spec, const std::string& file) {
    if (file.empty()) return;
    if (spec.scene().has_scene_name()) {
        spec.set_environment_file(file);  // the server reads it from the scene's folder
        return;
    }
    if (!spec.scene().has_gltf())
        throw CliError("--environment goes with a .gltf scene or a scene name, not a .glb");
    std::string bytes;
    try {
        bytes = readFile(file);
    } catch (const std::exception&) {
        throw CliError("cannot read environment image '" + file + "'");
    }
    std::string uri = "partita-environment/" + fs::path(file).filename().string();
    auto* res = spec.mutable_scene()->mutable_gltf()->add_resources();
    res->set_uri(uri);
    res->set_data(std::move(bytes));
    spec.set_environment_file(uri);
}

partita::v1::SceneSource loadSceneSource(const SceneArgument& scene) {
    partita::v1::SceneSource source;
    if (scene.text.empty()) throw CliError("the scene is empty");
    if (!scene.isFile) {
        source.set_scene_name(scene.text);
        return source;
    }
    const fs::path path = scene.text;
    std::error_code ec;
    if (!fs::exists(path, ec)) throw CliError("scene file '" + path.string() + "' does not exist");
    if (!fs::is_regular_file(path, ec))
        throw CliError("scene '" + path.string() + "' is not a file");
    std::string bytes;
    try {
        bytes = readFile(path);
    } catch (const std::exception&) {
        throw CliError("cannot read scene file '" + path.string() + "'");
    }
    const bool glb = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    if (glb) {
        checkGlbHasNoExternalFiles(path, bytes);
        source.set_glb(std::move(bytes));
        return source;
    }
    json doc = json::parse(bytes, nullptr, false);
    if (doc.is_discarded() || !doc.is_object())
        throw CliError("scene file '" + path.string() + "' is not valid glTF JSON");
    auto* upload = source.mutable_gltf();
    const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
    for (const std::string& uri : externalUris(doc)) {
        const fs::path file = resolveUri(path, folder, uri);
        auto* res = upload->add_resources();
        res->set_uri(uri);
        try {
            res->set_data(readFile(file));
        } catch (const std::exception&) {
            throw CliError("cannot read resource '" + uri + "' of scene '" + path.string() + "'");
        }
    }
    upload->set_gltf(std::move(bytes));
    return source;
}

}  // namespace partita::cli
