// The bridge between tinygltf and our I/O policy: filesystem callbacks that send every read
// through a ResourceResolver (tinygltf never touches the filesystem itself), and an image
// "loader" that only keeps the encoded bytes so that we decode images ourselves, later, with
// limits and bounds checks (tinygltf hands image bufferViews to its loader unchecked).
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <map>
#include <string>

#include "gltf/resource_resolver.h"

namespace partita::gltf {

class TinyGltfIo {
  public:
    TinyGltfIo(const ResourceResolver& resolver, uint64_t maxFileBytes)
        : resolver_(resolver), maxFileBytes_(maxFileBytes) {}
    TinyGltfIo(const TinyGltfIo&) = delete;
    TinyGltfIo& operator=(const TinyGltfIo&) = delete;

    /// Points `loader`'s filesystem and image callbacks at this object (which must outlive it).
    void install(tinygltf::TinyGLTF& loader);

    /// Why reading `uri` failed, or empty when it did not (or was never tried).
    std::string errorFor(const std::string& uri) const;
    /// The first read error met, for a clear message when tinygltf gives up on a buffer.
    const std::string& firstError() const { return firstError_; }

  private:
    static bool fileExists(const std::string& path, void* self);
    static std::string expandFilePath(const std::string& path, void* self);
    static bool readWholeFile(std::vector<unsigned char>* out, std::string* err,
                              const std::string& path, void* self);
    static bool writeWholeFile(std::string* err, const std::string& path,
                               const std::vector<unsigned char>& contents, void* self);
    static bool keepEncodedImage(tinygltf::Image* image, int imageIndex, std::string* err,
                                 std::string* warn, int reqWidth, int reqHeight,
                                 const unsigned char* bytes, int size, void* self);

    const ResourceResolver& resolver_;
    uint64_t maxFileBytes_;
    std::map<std::string, std::string> errors_;
    std::string firstError_;
};

/// Percent-decoding exactly as tinygltf applies it to uris before asking for a file (it also
/// turns '+' into a space), so that a uri can be matched with the error recorded for it.
std::string decodeUriLikeTinygltf(const std::string& uri);

}  // namespace partita::gltf
