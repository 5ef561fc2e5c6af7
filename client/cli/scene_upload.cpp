#include "cli/scene_upload.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string_view>
#include <thread>
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

/// One UploadScene stream of `files`; the upload's id in `id` when it succeeds.
grpc::Status sendOnce(Connection& conn, const partita::v1::UploadHeader& header,
                      const std::vector<std::string_view>& files, std::string& id) {
    grpc::ClientContext context;
    conn.prepare(context, 3600);
    partita::v1::UploadSceneResponse response;
    auto stream = conn.stub().UploadScene(&context, &response);
    partita::v1::UploadChunk chunk;
    *chunk.mutable_header() = header;
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
    id = response.upload_id();
    return status;
}

/// The server receives as many uploads as it allows at once (--max-upload-streams): a refusal
/// that passes when one of them ends, unlike the other RESOURCE_EXHAUSTED ones (size, store).
bool serverBusy(const grpc::Status& status) {
    return status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED &&
           status.error_message().find("--max-upload-streams") != std::string::npos;
}

}  // namespace

void uploadScene(Connection& conn, partita::v1::SceneSource& source) {
    if (!source.has_glb() && !source.has_gltf()) return;
    partita::v1::UploadHeader header;
    const std::vector<std::string_view> files = filesOf(source, header);
    // A busy server is waited for (at most 10 minutes, backing off to 5 s between tries).
    using Clock = std::chrono::steady_clock;
    const Clock::time_point giveUp = Clock::now() + std::chrono::minutes(10);
    std::chrono::milliseconds pause(250);
    std::string id;
    grpc::Status status;
    for (bool announced = false;; pause = std::min(pause * 2, std::chrono::milliseconds(5000))) {
        status = sendOnce(conn, header, files, id);
        if (!serverBusy(status) || Clock::now() + pause > giveUp) break;
        if (!announced)
            std::fprintf(stderr,
                         "partita: the server is receiving as many uploads as it takes; "
                         "waiting to send the scene\n");
        announced = true;
        std::this_thread::sleep_for(pause);
    }
    if (!status.ok()) conn.fail(status, "upload scene");
    source.Clear();
    source.set_upload_id(id);
}

}  // namespace partita::cli
