// SCENE on the command line: a .gltf/.glb file that is uploaded with the job, or the name of a
// scene under the server's scene root.
//
// It is a file when it ends in .gltf or .glb (any case) or names an existing regular file; such
// a file must exist. Anything else is a scene name. A .glb is sent as its bytes. A .gltf is sent
// with every resource its buffers[].uri and images[].uri name (data: URIs stay inline), read
// relative to the .gltf's folder and keyed by the uri exactly as written. A uri that is
// absolute, has a scheme, or leads outside the folder (also through a symlink) is refused here,
// before anything is sent; the server refuses it too. A .glb whose JSON names external files is
// refused (the protocol uploads a .glb as bytes alone): convert it to .gltf.
#pragma once

#include <string>

#include "cli/proto.h"

namespace partita::cli {

struct SceneArgument {
    bool isFile = false;
    std::string text;  // as given
};

SceneArgument classifyScene(const std::string& scene);

/// The SceneSource for a job; reads and checks files now. Throws CliError.
partita::v1::SceneSource loadSceneSource(const SceneArgument& scene);

/// --environment FILE for a job whose scene is already in `spec`: with an uploaded .gltf the
/// local image travels with it as one more resource (uri "partita-environment/<name>"); with a
/// named scene FILE names an image in that scene's folder on the server. A .glb upload has no
/// room for it. Throws CliError.
void addEnvironmentImage(partita::v1::JobSpec& spec, const std::string& file);

/// A short name for outputs: the file's stem or the scene name ("cornell").
std::string sceneStem(const SceneArgument& scene);

/// glTF uris are URI references: "%20" is a space. Throws CliError on a malformed escape.
std::string percentDecode(const std::string& uri);

}  // namespace partita::cli
