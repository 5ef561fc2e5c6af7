// Where a job's scene comes from: a named scene under the scene root, or bytes uploaded with the
// job. Names are untrusted: a name is one path component (no '/', no "..", not absolute), and the
// file it resolves to, symlinks followed, must lie inside the scene root. Resources of a named
// scene are read only from its own folder, resources of an upload only from the upload (the
// core's resolvers enforce that for every glTF uri).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "gltf/gltf_loader.h"
#include "proto.h"
#include "scene_data.h"

namespace partita::server {

struct SceneEntry {
    std::string name;
    std::string file;  // relative to the scene root
};

class SceneSource {
  public:
    /// `root` may be empty: then there are no named scenes.
    explicit SceneSource(const std::filesystem::path& root);

    const std::filesystem::path& root() const { return root_; }

    /// "" when `name` is an acceptable scene name, else why not.
    static std::string checkName(const std::string& name);

    /// The file of the named scene. On failure returns an empty path with the gRPC code
    /// (INVALID_ARGUMENT for a malformed name or one escaping the root, NOT_FOUND for no such
    /// scene) and a message.
    std::filesystem::path resolve(const std::string& name, grpc::StatusCode& code,
                                  std::string& error) const;

    /// Scenes addressable by name: <root>/<name>/<name>.gltf|.glb and <root>/<name>.glb.
    std::vector<SceneEntry> list() const;

    /// The bytes of resource `uri` of a named scene: a file in its folder, by the rules of glTF
    /// uris (nothing outside the folder). Throws SceneLoadError.
    std::vector<uint8_t> readNamedResource(const std::string& name, const std::string& uri,
                                           uint64_t maxBytes) const;
    /// The bytes of resource `uri` uploaded with a .gltf scene. Throws SceneLoadError.
    static std::vector<uint8_t> readUploadedResource(const pb::SceneSource& upload,
                                                     const std::string& uri);

    /// Loads a named scene. Throws SceneLoadError (one line) for anything wrong.
    SceneData loadNamed(const std::string& name) const;

    /// Loads an uploaded scene (a SceneSource with glb or gltf set). Throws SceneLoadError.
    static SceneData loadUpload(const pb::SceneSource& upload, uint64_t maxBytes);

    /// Bytes of a named scene's files (its folder, or its .glb); 0 when there is no such scene.
    uint64_t sceneBytes(const std::string& name) const;

    /// Total bytes of an upload (the glTF/GLB and every resource).
    static uint64_t uploadBytes(const pb::SceneSource& source);

  private:
    /// resolve() without the list of available scenes in the message.
    std::filesystem::path find(const std::string& name, grpc::StatusCode& code,
                               std::string& error) const;

    std::filesystem::path root_;  // canonical, or empty
};

}  // namespace partita::server
