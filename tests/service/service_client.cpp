#include "service_client.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <functional>
#include <optional>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <thread>

namespace partita::test {

using namespace std::chrono_literals;

Uploaded sendUpload(pb::Partita::Stub& stub, const pb::UploadHeader& header,
                    const std::vector<std::string>& pieces, bool sendHeader) {
    auto ctx = context(120s);
    pb::UploadSceneResponse response;
    auto stream = stub.UploadScene(ctx.get(), &response);
    pb::UploadChunk chunk;
    bool open = true;
    if (sendHeader) {
        *chunk.mutable_header() = header;
        open = stream->Write(chunk);
        chunk.clear_header();
    }
    for (const auto& piece : pieces) {
        if (!open) break;
        chunk.set_data(piece);
        open = stream->Write(chunk);
    }
    if (open) stream->WritesDone();
    Uploaded out;
    out.status = stream->Finish();
    out.id = response.upload_id();
    return out;
}

Uploaded upload(pb::Partita::Stub& stub, const pb::SceneSource& source, size_t pieceBytes) {
    pb::UploadHeader header;
    std::string all;
    if (source.has_glb()) {
        header.set_format(pb::SCENE_FORMAT_GLB);
        header.set_scene_bytes(int64_t(source.glb().size()));
        all = source.glb();
    } else {
        header.set_format(pb::SCENE_FORMAT_GLTF);
        header.set_scene_bytes(int64_t(source.gltf().gltf().size()));
        all = source.gltf().gltf();
        for (const auto& r : source.gltf().resources()) {
            auto* file = header.add_resources();
            file->set_uri(r.uri());
            file->set_size(int64_t(r.data().size()));
            all += r.data();
        }
    }
    std::vector<std::string> pieces;
    for (size_t at = 0; at < all.size(); at += pieceBytes)
        pieces.push_back(all.substr(at, pieceBytes));
    return sendUpload(stub, header, pieces);
}

pb::ServerInfo serverInfo(pb::Partita::Stub& stub) {
    pb::ServerInfo info;
    auto ctx = context(10s);
    EXPECT_TRUE(stub.GetServerInfo(ctx.get(), pb::ServerInfoRequest{}, &info).ok());
    return info;
}

uint64_t procStatusKiB(pid_t pid, const std::string& field) {
    std::string status = readFile("/proc/" + std::to_string(pid) + "/status");
    size_t at = status.find(field + ":");
    if (at == std::string::npos) return 0;
    return std::stoull(status.substr(at + field.size() + 1));
}

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void writeFile(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

namespace {

/// fork + exec of partitad with stdout and stderr into `logFile`.
pid_t spawn(const std::vector<std::string>& args, const fs::path& logFile) {
    std::vector<char*> argv;
    std::string exe = PARTITAD_PATH;
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = ::fork();
    if (pid == 0) {
        int fd = ::open(logFile.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) {
            ::dup2(fd, 1);
            ::dup2(fd, 2);
        }
        ::execv(exe.c_str(), argv.data());
        ::_exit(127);
    }
    return pid;
}

/// Waits for `pid` up to `timeout`; the exit code, 128 + signal, or -1 on timeout.
int waitExit(pid_t pid, std::chrono::milliseconds timeout) {
    auto end = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        int status = 0;
        pid_t r = ::waitpid(pid, &status, WNOHANG);
        if (r == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        if (r < 0) return -2;
        if (std::chrono::steady_clock::now() > end) return -1;
        std::this_thread::sleep_for(10ms);
    }
}

}  // namespace

Daemon::Daemon(const fs::path& store, std::vector<std::string> extra, const fs::path& sceneRoot) {
    fs::path portFile = runDir_ / "port";
    std::vector<std::string> args = {
        "--store",     store.string(),    "--threads",    "2",
        "--port-file", portFile.string(), "--scene-root", sceneRoot.string()};
    if (std::find(extra.begin(), extra.end(), "--listen") == extra.end()) {
        args.push_back("--listen");
        args.push_back("127.0.0.1:0");
    }
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = spawn(args, runDir_ / "log");
    auto end = std::chrono::steady_clock::now() + 20s;
    while (std::chrono::steady_clock::now() < end) {
        std::string text = readFile(portFile);
        if (!text.empty() && text.back() == '\n') {
            port_ = std::stoi(text);
            return;
        }
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            ADD_FAILURE() << "partitad exited during start-up:\n" << log();
            return;
        }
        std::this_thread::sleep_for(10ms);
    }
    ADD_FAILURE() << "partitad did not write its port file within 20 s:\n" << log();
}

Daemon::~Daemon() {
    if (pid_ > 0) {
        ::kill(pid_, SIGKILL);
        waitExit(pid_, 10s);
    }
}

std::shared_ptr<grpc::Channel> Daemon::channel() const {
    grpc::ChannelArguments args;
    args.SetMaxReceiveMessageSize(-1);
    args.SetMaxSendMessageSize(-1);
    // A fresh connection per channel, as separate client programs would have.
    args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
    return grpc::CreateCustomChannel(address(), grpc::InsecureChannelCredentials(), args);
}

std::string Daemon::log() const { return readFile(runDir_ / "log"); }

int Daemon::stop(int signal, std::chrono::seconds timeout) {
    if (pid_ <= 0) return -3;
    ::kill(pid_, signal);
    int code = waitExit(pid_, timeout);
    if (code != -1) pid_ = -1;
    return code;
}

std::pair<int, std::string> runPartitad(const std::vector<std::string>& args,
                                        std::chrono::seconds timeout) {
    TempDir dir;
    pid_t pid = spawn(args, dir / "log");
    int code = waitExit(pid, timeout);
    if (code == -1) {
        ::kill(pid, SIGKILL);
        waitExit(pid, 10s);
    }
    return {code, readFile(dir / "log")};
}

std::unique_ptr<grpc::ClientContext> context(std::chrono::milliseconds deadline,
                                             const std::string& token) {
    auto ctx = std::make_unique<grpc::ClientContext>();
    ctx->set_deadline(std::chrono::system_clock::now() + deadline);
    if (!token.empty()) ctx->AddMetadata("authorization", "Bearer " + token);
    return ctx;
}

pb::JobSpec sceneSpec(const std::string& scene, int width, int height, double spp, uint64_t seed) {
    pb::JobSpec spec;
    spec.mutable_scene()->set_scene_name(scene);
    spec.set_width(width);
    spec.set_height(height);
    spec.set_algorithm("pt");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SAMPLES_PER_PIXEL);
    spec.mutable_budget()->set_amount(spp);
    spec.set_seed(seed);
    return spec;
}

Submitted submit(pb::Partita::Stub& stub, const pb::JobSpec& spec, const std::string& token) {
    pb::SubmitJobRequest request;
    *request.mutable_spec() = spec;
    pb::SubmitJobResponse response;
    auto ctx = context(60s, token);
    Submitted out;
    out.status = stub.SubmitJob(ctx.get(), request, &response);
    out.id = response.job_id();
    return out;
}

std::vector<pb::JobState> WatchLog::states() const {
    std::vector<pb::JobState> out;
    for (const auto& e : events)
        if (e.has_state()) out.push_back(e.state().state());
    return out;
}

std::vector<const pb::PreviewFrame*> WatchLog::frames() const {
    std::vector<const pb::PreviewFrame*> out;
    for (const auto& e : events)
        if (e.has_preview()) out.push_back(&e.preview());
    return out;
}

std::optional<pb::Job> WatchLog::last() const {
    for (auto it = events.rbegin(); it != events.rend(); ++it)
        if (it->has_state()) return it->state();
    return std::nullopt;
}

pb::WatchJobRequest watchRequest(const std::string& id, bool previews, bool raw) {
    pb::WatchJobRequest request;
    request.set_job_id(id);
    request.set_previews(previews);
    request.set_raw_previews(raw);
    return request;
}

WatchLog watch(pb::Partita::Stub& stub, const std::string& id, bool previews, bool raw,
               std::chrono::milliseconds deadline) {
    auto ctx = context(deadline);
    auto reader = stub.WatchJob(ctx.get(), watchRequest(id, previews, raw));
    WatchLog log;
    pb::JobEvent event;
    while (reader->Read(&event)) log.events.push_back(event);
    log.status = reader->Finish();
    return log;
}

namespace {

/// Polls GetJob every `poll` until `done(job)` holds or `timeout` passes.
std::optional<pb::Job> pollJob(pb::Partita::Stub& stub, const std::string& id,
                               const std::function<bool(const pb::Job&)>& done,
                               std::chrono::milliseconds timeout, std::chrono::milliseconds poll) {
    auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
        pb::GetJobRequest request;
        request.set_job_id(id);
        pb::Job job;
        auto ctx = context(10s);
        if (stub.GetJob(ctx.get(), request, &job).ok() && done(job)) return job;
        std::this_thread::sleep_for(poll);
    }
    return std::nullopt;
}

}  // namespace

pb::Job waitForEnd(pb::Partita::Stub& stub, const std::string& id,
                   std::chrono::milliseconds timeout) {
    auto ended = [](const pb::Job& job) {
        return job.state() == pb::JOB_STATE_DONE || job.state() == pb::JOB_STATE_FAILED ||
               job.state() == pb::JOB_STATE_CANCELLED;
    };
    return pollJob(stub, id, ended, timeout, 20ms).value_or(pb::Job{});
}

bool waitForState(pb::Partita::Stub& stub, const std::string& id, pb::JobState state,
                  std::chrono::milliseconds timeout) {
    auto reached = [state](const pb::Job& job) { return job.state() == state; };
    return pollJob(stub, id, reached, timeout, 5ms).has_value();
}

Fetched fetch(pb::Partita::Stub& stub, const std::string& id, pb::ResultKind kind) {
    pb::FetchResultRequest request;
    request.set_job_id(id);
    request.set_kind(kind);
    auto ctx = context(60s);
    auto reader = stub.FetchResult(ctx.get(), request);
    Fetched out;
    pb::ResultChunk chunk;
    uint64_t total = 0;
    while (reader->Read(&chunk)) {
        if (out.chunks == 0) total = chunk.total_size();
        out.chunksConsistent &= chunk.offset() == out.bytes.size() && chunk.total_size() == total;
        out.bytes += chunk.data();
        ++out.chunks;
    }
    out.status = reader->Finish();
    out.chunksConsistent &= out.bytes.size() == total;
    return out;
}

namespace {

void pad(std::string& s, char with) {
    while (s.size() % 4) s.push_back(with);
}

template <class T>
void append(std::string& bin, const std::vector<T>& v) {
    bin.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

void appendU32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

}  // namespace

std::string makeGridGlb(int n) {
    using nlohmann::json;
    std::vector<float> positions;
    std::vector<uint32_t> indices;
    positions.reserve(size_t(n) * n * 3);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            float fx = float(x) / float(n - 1), fy = float(y) / float(n - 1);
            positions.insert(positions.end(),
                             {fx * 2 - 1, fy * 2 - 1, 0.02f * float((x * 7 + y * 13) % 5)});
        }
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            uint32_t a = uint32_t(y * n + x), b = a + 1, c = a + uint32_t(n), d = c + 1;
            indices.insert(indices.end(), {a, b, d, a, d, c});
        }
    std::vector<float> lightPos = {-0.3f, -0.3f, 1.5f, 0.3f,  -0.3f, 1.5f,
                                   0.3f,  0.3f,  1.5f, -0.3f, 0.3f,  1.5f};
    std::vector<uint32_t> lightIdx = {0, 2, 1, 0, 3, 2};
    std::string bin;
    size_t o0 = bin.size();
    append(bin, positions);
    size_t o1 = bin.size();
    append(bin, indices);
    size_t o2 = bin.size();
    append(bin, lightPos);
    size_t o3 = bin.size();
    append(bin, lightIdx);
    size_t end = bin.size();
    json j = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0, 1, 2}}}}},
        {"nodes", {{{"mesh", 0}}, {{"mesh", 1}}, {{"camera", 0}, {"translation", {0, 0, 3}}}}},
        {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.01}}}}}},
        {"materials",
         {{{"pbrMetallicRoughness",
            {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0}}}},
          {{"emissiveFactor", {1, 1, 1}}}}},
        {"meshes",
         {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}},
          {{"primitives",
            {{{"attributes", {{"POSITION", 2}}}, {"indices", 3}, {"material", 1}}}}}}},
        {"buffers", {{{"byteLength", end}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", o0}, {"byteLength", o1 - o0}},
          {{"buffer", 0}, {"byteOffset", o1}, {"byteLength", o2 - o1}},
          {{"buffer", 0}, {"byteOffset", o2}, {"byteLength", o3 - o2}},
          {{"buffer", 0}, {"byteOffset", o3}, {"byteLength", end - o3}}}},
        {"accessors",
         {{{"bufferView", 0},
           {"componentType", 5126},
           {"count", positions.size() / 3},
           {"type", "VEC3"},
           {"min", {-1, -1, 0}},
           {"max", {1, 1, 0.08}}},
          {{"bufferView", 1},
           {"componentType", 5125},
           {"count", indices.size()},
           {"type", "SCALAR"}},
          {{"bufferView", 2},
           {"componentType", 5126},
           {"count", 4},
           {"type", "VEC3"},
           {"min", {-0.3, -0.3, 1.5}},
           {"max", {0.3, 0.3, 1.5}}},
          {{"bufferView", 3}, {"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}}}};
    std::string text = j.dump();
    pad(text, ' ');
    pad(bin, '\0');
    std::string glb;
    appendU32(glb, 0x46546C67);  // "glTF"
    appendU32(glb, 2);
    appendU32(glb, uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    appendU32(glb, uint32_t(text.size()));
    appendU32(glb, 0x4E4F534A);  // JSON
    glb += text;
    appendU32(glb, uint32_t(bin.size()));
    appendU32(glb, 0x004E4942);  // BIN
    glb += bin;
    return glb;
}

std::string gltfWithBufferUri(const std::string& uri, size_t byteLength) {
    using nlohmann::json;
    json j = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}}}},
              {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
              {"buffers", {{{"uri", uri}, {"byteLength", byteLength}}}},
              {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}}}},
              {"accessors",
               {{{"bufferView", 0},
                 {"componentType", 5126},
                 {"count", 3},
                 {"type", "VEC3"},
                 {"min", {0, 0, 0}},
                 {"max", {1, 1, 0}}}}}};
    return j.dump();
}

}  // namespace partita::test
