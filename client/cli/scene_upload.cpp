#include "cli/scene_upload.h"

#include <algorithm>
#include <string_view>
#include <vector>

namespace partita::cli {

namespace {

constexpr size_t kPieceBytes = size_t(1) << 20;

/// The files of an upload in the order the stream sends them: the scene file, then resources.
std::vector<std::string_view> filesOf(const partita::v1::SceneSource& source,
                                      partita::v1::UploadHeader& header) {
    std::vector<std::string_view> files;
    if (source.has_glb()) {
        header.set_format(partita::v1::SCENE_FORMAT_GLB);
        files.push_back(source.glb());
    } else {
        header.set_format(partita::v1::SCENE_FORMAT_GLTF);
        files.push_back(source.gltf().gltf());
        for (const auto& r : source.gltf().resources()) {
            auto* file = header.add_resources();
            file->set_uri(r.uri());
            file->set_size(int64_t(r.data().size()));
            files.push_back(r.data());
        }
    }
    header.set_scene_bytes(int64_t(files.front().size()));
    return files;
}

}  // namespace

void uploadScene(Connection& conn, partita::v1::SceneSource& source) {
    if (!source.has_glb() && !source.has_gltf()) return;
    grpc::ClientContext context;
    conn.prepare(context, 3600);
    partita::v1::UploadSceneResponse response;
    auto stream = conn.stub().UploadScene(&context, &response);

    partita::v1::UploadChunk chunk;
    const std::vector<std::string_view> files = filesOf(source, *chunk.mutable_header());
    bool open = stream->Write(chunk);
    chunk.clear_header();
    for (std::string_view file : files)
        for (size_t at = 0; open && at < file.size(); at += kPieceBytes) {
            chunk.set_data(std::string(file.substr(at, kPieceBytes)));
            open = stream->Write(chunk);
        }
    // A refusal ends the stream early (Write fails); Finish says why.
    if (open) stream->WritesDone();
    grpc::Status status = stream->Finish();
    if (!status.ok()) conn.fail(status, "upload scene");
    source.Clear();
    source.set_upload_id(response.upload_id());
}

}  // namespace partita::cli
