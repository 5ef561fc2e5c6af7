#include "gltf/resource_resolver.h"

#include <algorithm>
#include <fstream>
#include <system_error>

namespace partita {

namespace fs = std::filesystem;

namespace {

bool hasDotDotComponent(const std::string& uri) {
    size_t start = 0;
    while (start <= uri.size()) {
        size_t end = uri.find('/', start);
        if (end == std::string::npos) end = uri.size();
        if (uri.compare(start, end - start, "..") == 0 && end - start == 2) return true;
        start = end + 1;
    }
    return false;
}

/// True when `path` is `root` or lies below it (both canonical, compared component-wise so that
/// "/a/bc" is not inside "/a/b").
bool isInside(const fs::path& path, const fs::path& root) {
    auto [r, p] = std::mismatch(root.begin(), root.end(), path.begin(), path.end());
    return r == root.end();
}

std::string refused(const std::string& uri, const std::string& why) {
    return "uri '" + printableUri(uri) + "' refused: " + why;
}

}  // namespace

std::string printableUri(const std::string& uri) {
    constexpr size_t kMax = 160;
    std::string out;
    for (size_t i = 0; i < uri.size() && i < kMax; ++i) {
        unsigned char c = static_cast<unsigned char>(uri[i]);
        out += (c < 0x20 || c == 0x7f) ? '?' : char(c);
    }
    if (uri.size() > kMax) out += "...";
    return out;
}

std::string checkRelativeUri(const std::string& uri) {
    if (uri.empty()) return "empty uri";
    if (uri.find('\0') != std::string::npos) return "it contains a NUL byte";
    if (uri.find('\\') != std::string::npos) return "it contains a backslash";
    if (uri.front() == '/') return "absolute paths are not allowed";
    if (uri.find(':') != std::string::npos) {
        // tinygltf decodes the base64 data: URIs it knows; anything else reaching a resolver is
        // a data: URI in a form we do not support, a scheme (file:, http:) or a drive letter.
        if (uri.rfind("data:", 0) == 0)
            return "unsupported data: URI (only base64 with a glTF buffer or PNG/JPEG type)";
        return "schemes and drive letters are not allowed (':' in uri)";
    }
    if (hasDotDotComponent(uri)) return "'..' components are not allowed";
    return {};
}

FolderResolver::FolderResolver(fs::path root, uint64_t maxFileBytes) : maxFileBytes_(maxFileBytes) {
    std::error_code ec;
    root_ = fs::canonical(root, ec);
    if (ec) root_ = fs::weakly_canonical(fs::absolute(root, ec), ec);
}

std::optional<std::vector<uint8_t>> FolderResolver::read(const std::string& uri,
                                                         std::string& error) const {
    if (std::string why = checkRelativeUri(uri); !why.empty()) {
        error = refused(uri, why);
        return std::nullopt;
    }
    // Canonicalising resolves every symlink on the way, so a link that points out of the folder
    // is caught by the prefix check below, while links inside the folder keep working.
    std::error_code ec;
    fs::path path = fs::weakly_canonical(root_ / fs::path(uri), ec);
    if (ec) {
        error = refused(uri, ec.message());
        return std::nullopt;
    }
    if (!isInside(path, root_)) {
        error = refused(uri, "it resolves outside the scene folder");
        return std::nullopt;
    }
    auto status = fs::status(path, ec);
    if (ec || !fs::exists(status)) {
        error = "resource '" + printableUri(uri) + "' not found in the scene folder";
        return std::nullopt;
    }
    if (!fs::is_regular_file(status)) {
        error = "resource '" + printableUri(uri) + "' is not a regular file";
        return std::nullopt;
    }
    uint64_t size = fs::file_size(path, ec);
    if (ec || size > maxFileBytes_) {
        error = "resource '" + printableUri(uri) + "' is larger than the limit of " +
                std::to_string(maxFileBytes_) + " bytes";
        return std::nullopt;
    }
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> bytes(size);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size))) {
        error = "resource '" + printableUri(uri) + "' could not be read";
        return std::nullopt;
    }
    return bytes;
}

std::optional<std::vector<uint8_t>> MemoryResolver::read(const std::string& uri,
                                                         std::string& error) const {
    if (std::string why = checkRelativeUri(uri); !why.empty()) {
        error = refused(uri, why);
        return std::nullopt;
    }
    auto it = files_.find(uri);
    if (it == files_.end()) {
        // "./a.bin" and "dir//a.bin" name the same upload as "a.bin" and "dir/a.bin".
        it = files_.find(fs::path(uri).lexically_normal().generic_string());
    }
    if (it == files_.end()) {
        error = "resource '" + printableUri(uri) + "' was not uploaded with the scene";
        return std::nullopt;
    }
    return it->second;
}

}  // namespace partita
