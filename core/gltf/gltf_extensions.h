// Which glTF extensions the loader honours. tinygltf 2.7 ignores `extensionsRequired`, so a file
// that needs, say, Draco would otherwise "load" with garbage accessors: we check it ourselves.
#pragma once

#include <string>
#include <vector>

namespace partita::gltf {

struct LoadContext;

/// True for the extensions whose data the loader reads.
bool isSupportedExtension(const std::string& name);

/// SceneLoadError naming the first required extension we cannot honour.
void checkRequiredExtensions(const std::vector<std::string>& required);

/// A warning for each extension in `extensionsUsed` that we ignore.
void warnAboutIgnoredExtensions(LoadContext& ctx);

}  // namespace partita::gltf
