#include "gltf/gltf_io.h"

namespace partita::gltf {

namespace {
int hexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;  // tinygltf maps invalid hex digits to 0 as well
}
}  // namespace

std::string decodeUriLikeTinygltf(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && i + 2 < uri.size()) {
            out += char(hexValue(uri[i + 1]) << 4 | hexValue(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

void TinyGltfIo::install(tinygltf::TinyGLTF& loader) {
    tinygltf::FsCallbacks callbacks{};
    callbacks.FileExists = &TinyGltfIo::fileExists;
    callbacks.ExpandFilePath = &TinyGltfIo::expandFilePath;
    callbacks.ReadWholeFile = &TinyGltfIo::readWholeFile;
    callbacks.WriteWholeFile = &TinyGltfIo::writeWholeFile;
    callbacks.user_data = this;
    loader.SetFsCallbacks(callbacks);
    loader.SetImageLoader(&TinyGltfIo::keepEncodedImage, this);
}

std::string TinyGltfIo::errorFor(const std::string& uri) const {
    auto it = errors_.find(uri);
    return it == errors_.end() ? std::string() : it->second;
}

// tinygltf asks FileExists(base_dir + uri) first; we load with an empty base_dir, so the path it
// asks about is the (percent-decoded) uri itself. Saying "yes" lets ReadWholeFile report the
// resolver's reason instead of tinygltf's generic "File not found".
bool TinyGltfIo::fileExists(const std::string&, void*) { return true; }

// The default expands `~` and environment variables (wordexp): never wanted for untrusted uris.
std::string TinyGltfIo::expandFilePath(const std::string& path, void*) { return path; }

bool TinyGltfIo::readWholeFile(std::vector<unsigned char>* out, std::string* err,
                               const std::string& path, void* self) {
    auto* io = static_cast<TinyGltfIo*>(self);
    std::string error;
    std::optional<std::vector<uint8_t>> bytes = io->resolver_.read(path, error);
    if (bytes && bytes->size() > io->maxFileBytes_) {
        bytes.reset();
        error = "resource '" + printableUri(path) + "' is larger than the limit of " +
                std::to_string(io->maxFileBytes_) + " bytes";
    }
    if (!bytes) {
        if (error.empty()) error = "resource '" + printableUri(path) + "' could not be read";
        io->errors_.emplace(path, error);
        if (io->firstError_.empty()) io->firstError_ = error;
        if (err) *err = error;
        return false;
    }
    *out = std::move(*bytes);
    return true;
}

bool TinyGltfIo::writeWholeFile(std::string* err, const std::string&,
                                const std::vector<unsigned char>&, void*) {
    if (err) *err = "the glTF loader never writes files";
    return false;
}

bool TinyGltfIo::keepEncodedImage(tinygltf::Image* image, int, std::string*, std::string*, int, int,
                                  const unsigned char* bytes, int size, void*) {
    // For an image stored in a bufferView, tinygltf passes a pointer it computed without checking
    // the view against its buffer: do not touch it; gltf_textures reads the view bounds-checked.
    if (image->bufferView >= 0) return true;
    if (bytes && size > 0) image->image.assign(bytes, bytes + size);
    image->as_is = true;  // encoded bytes, decoded later by gltf_textures
    return true;
}

}  // namespace partita::gltf
