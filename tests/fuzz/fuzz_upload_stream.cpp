// libFuzzer target for streamed uploads (server/upload_staging.h): a header and pieces of bytes
// as a client may send them, in any sizes. Whatever arrives, nothing may crash; an upload that
// finishes must be stored as the SceneSource its header and bytes describe, one that sends more
// or fewer bytes than declared must be refused.
#include <fuzzer/FuzzedDataProvider.h>
#include <stdlib.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "quiet_logs.h"
#include "upload_staging.h"

namespace ps = partita::server;
namespace fs = std::filesystem;

namespace {

fs::path storeDir() {
    static const fs::path dir = [] {
        char name[] = "/tmp/partita-fuzz-upload-XXXXXX";
        return fs::path(::mkdtemp(name));
    }();
    return dir;
}

ps::ServiceLimits& limits() {
    static ps::ServiceLimits l = [] {
        ps::ServiceLimits out;
        out.uploadTtlSeconds = 0;  // every finished upload goes at the next one's start
        return out;
    }();
    return l;
}

ps::pb::UploadHeader headerFrom(FuzzedDataProvider& in) {
    ps::pb::UploadHeader h;
    h.set_format(ps::pb::SceneFormat(in.ConsumeIntegralInRange<int>(0, 3)));
    h.set_scene_bytes(in.ConsumeIntegralInRange<int64_t>(-2, 64));
    for (int n = in.ConsumeIntegralInRange<int>(0, 4); n > 0; --n) {
        auto* r = h.add_resources();
        r->set_uri(in.ConsumeRandomLengthString(16));
        r->set_size(in.ConsumeIntegralInRange<int64_t>(-1, 32));
    }
    return h;
}

/// The SceneSource that `header` and the bytes `sent` describe.
ps::pb::SceneSource expected(const ps::pb::UploadHeader& h, const std::string& sent) {
    ps::pb::SceneSource s;
    size_t at = size_t(h.scene_bytes());
    if (h.format() == ps::pb::SCENE_FORMAT_GLB) {
        s.set_glb(sent);
        return s;
    }
    s.mutable_gltf()->set_gltf(sent.substr(0, at));
    for (const auto& r : h.resources()) {
        auto* out = s.mutable_gltf()->add_resources();
        out->set_uri(r.uri());
        out->set_data(sent.substr(at, size_t(r.size())));
        at += size_t(r.size());
    }
    return s;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    partita::fuzz::quietLogs();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static ps::UploadStaging staging(
        storeDir(), limits(), [](uint64_t) { return grpc::Status::OK; }, [](uint64_t) {});
    FuzzedDataProvider in(data, size);
    const ps::pb::UploadHeader header = headerFrom(in);
    std::unique_ptr<ps::UploadWriter> writer;
    if (!staging.begin(header, writer).ok()) return 0;
    uint64_t declared = uint64_t(header.scene_bytes());
    for (const auto& r : header.resources()) declared += uint64_t(r.size());
    std::string sent;
    bool refused = false;
    while (in.remaining_bytes() > 0 && !refused) {
        std::string piece = in.ConsumeRandomLengthString(48);
        sent += piece;
        refused = !writer->append(piece).ok();
    }
    if (refused) {
        if (sent.size() <= declared) abort();  // refused bytes it had declared
        return 0;
    }
    ps::pb::UploadSceneResponse response;
    const bool finished = writer->finish(response).ok();
    if (finished != (sent.size() == declared)) abort();
    if (!finished) return 0;
    std::ifstream file(storeDir() / "uploads" / response.upload_id() / "upload.pb",
                       std::ios::binary);
    std::stringstream bytes;
    bytes << file.rdbuf();
    ps::pb::SceneSource stored;
    if (!stored.ParseFromString(bytes.str())) abort();
    if (stored.SerializeAsString() != expected(header, sent).SerializeAsString()) abort();
    return 0;
}
