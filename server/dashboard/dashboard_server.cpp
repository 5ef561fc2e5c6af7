#include "dashboard_server.h"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <fstream>

#include "assets.h"
#include "http_wire.h"
#include "job_event_stream.h"
#include "server_options.h"
#include "text.h"

namespace partita::server::dashboard {

namespace fs = std::filesystem;

namespace {

/// The Content-Length a request declares (0 when none).
uint64_t contentLength(const httplib::Request& req) {
    return std::strtoull(req.get_header_value("Content-Length").c_str(), nullptr, 10);
}

constexpr auto kEventWait = std::chrono::milliseconds(500);
constexpr auto kKeepAlive = std::chrono::seconds(10);  // an SSE comment when nothing happened
constexpr size_t kFileChunk = 1 << 20;

void sendStatus(httplib::Response& res, const grpc::Status& status) {
    res.status = httpStatus(status.error_code());
    res.set_content(errorJson(status), "application/json");
}

void sendJson(httplib::Response& res, google::protobuf::Message& message, int code = 200) {
    res.status = code;
    res.set_content(toJson(message), "application/json");
}

/// Host and port of "host:port" or "[v6]:port"; false when malformed.
bool splitAddress(const std::string& address, std::string& host, int& port) {
    size_t colon = address.rfind(':');
    if (colon == std::string::npos || colon + 1 == address.size()) return false;
    host = address.substr(0, colon);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
        host = host.substr(1, host.size() - 2);
    try {
        size_t used = 0;
        port = std::stoi(address.substr(colon + 1), &used);
        return used == address.size() - colon - 1 && port >= 0 && port <= 65535;
    } catch (const std::exception&) {
        return false;
    }
}

/// "event: NAME\ndata: JSON\n\n" (the JSON is one line).
std::string sseEvent(const JobEventStream::Event& event) {
    return "event: " + event.name + "\ndata: " + event.data + "\n\n";
}

void securityHeaders(httplib::Response& res) {
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_header("X-Frame-Options", "DENY");
    res.set_header("Referrer-Policy", "no-referrer");
    res.set_header("Content-Security-Policy",
                   "default-src 'self'; img-src 'self' data: blob:; style-src 'self'; "
                   "script-src 'self'; connect-src 'self'; frame-ancestors 'none'");
}

std::unique_ptr<httplib::Server> makeServer(const DashboardOptions& o) {
    if (o.tlsCert.empty()) return std::make_unique<httplib::Server>();
    auto tls = std::make_unique<httplib::SSLServer>(o.tlsCert.c_str(), o.tlsKey.c_str());
    if (!tls->is_valid())
        throw std::runtime_error("the dashboard cannot use TLS certificate '" + o.tlsCert.string() +
                                 "' with key '" + o.tlsKey.string() + "'");
    return tls;
}

}  // namespace

DashboardServer::DashboardServer(JobApi& api, const TokenAuth& auth, DashboardOptions options)
    : api_(api),
      options_(std::move(options)),
      access_(auth, isLoopbackAddress(options_.address), !options_.tlsCert.empty()) {}

DashboardServer::~DashboardServer() { stop(); }

int DashboardServer::start() {
    std::string host;
    int port = 0;
    if (!splitAddress(options_.address, host, port))
        throw std::runtime_error("--http takes host:port, not '" + options_.address + "'");
    server_ = makeServer(options_);
    // Every event stream holds a thread; the rest serve pages and the API.
    size_t threads = size_t(options_.maxEventStreams) + 8;
    server_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    server_->set_write_timeout(options_.writeTimeoutSeconds, 0);
    server_->set_read_timeout(5, 0);
    server_->set_keep_alive_timeout(5);
    // The largest body: a .glb streamed to /api/uploads (written to the store as it arrives).
    // Other bodies are held whole: the pre-routing check bounds them by jsonBodyLimit().
    server_->set_payload_max_length(size_t(api_.limits().maxUploadBytes) + (1 << 20));
    addRoutes();
    int bound = port == 0                           ? server_->bind_to_any_port(host)
                : server_->bind_to_port(host, port) ? port
                                                    : -1;
    if (bound <= 0)
        throw std::runtime_error("the dashboard cannot listen on '" + options_.address + "'");
    thread_ = std::thread([this] { server_->listen_after_bind(); });
    return bound;
}

void DashboardServer::stop() {
    stopping_ = true;
    if (server_) server_->stop();
    if (thread_.joinable()) thread_.join();
}

size_t DashboardServer::jsonBodyLimit() const {
    // A JSON spec may carry a .glb base64 (4/3 of its bytes) up to the gRPC message limit.
    return size_t(api_.limits().maxMessageBytes) / 3 * 4 + (1 << 20);
}

void DashboardServer::addRoutes() {
    server_->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
        securityHeaders(res);
        if (grpc::Status s = access_.check(req); !s.ok()) {
            spdlog::info("dashboard: refused {} {} from {}: {}", req.method,
                         quoteInput(req.path, 80), req.remote_addr, s.error_message());
            sendStatus(res, s);
            return httplib::Server::HandlerResponse::Handled;
        }
        if (std::string cookie = access_.loginCookie(req); !cookie.empty())
            res.set_header("Set-Cookie", cookie);
        // Before the body is read: only /api/uploads streams a large one.
        if (req.path != "/api/uploads" && contentLength(req) > jsonBodyLimit()) {
            sendStatus(res, {grpc::StatusCode::RESOURCE_EXHAUSTED,
                             "a request body is at most " + std::to_string(jsonBodyLimit()) +
                                 " bytes; send a scene to /api/uploads"});
            return httplib::Server::HandlerResponse::Handled;
        }
        return httplib::Server::HandlerResponse::Unhandled;
    });
    server_->set_error_handler([](const httplib::Request&, httplib::Response& res) {
        if (!res.body.empty()) return;
        grpc::StatusCode code = res.status == 404   ? grpc::StatusCode::NOT_FOUND
                                : res.status == 413 ? grpc::StatusCode::RESOURCE_EXHAUSTED
                                : res.status < 500  ? grpc::StatusCode::INVALID_ARGUMENT
                                                    : grpc::StatusCode::INTERNAL;
        int status = res.status;
        sendStatus(res, {code, "HTTP " + std::to_string(status)});
        res.status = status;
    });
    server_->set_exception_handler([](const httplib::Request& req, httplib::Response& res,
                                      std::exception_ptr ep) {
        std::string what = "unknown error";
        try {
            std::rethrow_exception(ep);
        } catch (const std::exception& e) {
            what = e.what();
        } catch (...) {
        }
        spdlog::error("dashboard: {} {} failed: {}", req.method, quoteInput(req.path, 80), what);
        sendStatus(res, {grpc::StatusCode::INTERNAL, what});
    });
    addPageRoutes();
    addJobRoutes();
    addEventRoute();
    addResultRoute();
}

void DashboardServer::addPageRoutes() {
    auto serve = [](const char* name) {
        return [name](const httplib::Request&, httplib::Response& res) {
            const Asset* asset = findAsset(name);
            res.set_content(asset->body.data(), asset->body.size(),
                            std::string(asset->contentType).c_str());
        };
    };
    server_->Get("/", serve("index.html"));
    server_->Get("/job", serve("job.html"));
    server_->Get(R"(/static/([A-Za-z0-9_.-]+))",
                 [](const httplib::Request& req, httplib::Response& res) {
                     const Asset* asset = findAsset(req.matches[1].str());
                     if (!asset || asset->name.find(".html") != std::string_view::npos)
                         return sendStatus(res, {grpc::StatusCode::NOT_FOUND, "no such file"});
                     res.set_content(asset->body.data(), asset->body.size(),
                                     std::string(asset->contentType).c_str());
                 });
}

void DashboardServer::addJobRoutes() {
    server_->Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
        pb::ServerInfo info;
        api_.serverInfo(info);
        sendJson(res, info);
    });
    server_->Get("/api/scenes", [this](const httplib::Request&, httplib::Response& res) {
        pb::ListScenesResponse scenes;
        api_.listScenes(scenes);
        sendJson(res, scenes);
    });
    server_->Get("/api/jobs", [this](const httplib::Request& req, httplib::Response& res) {
        pb::ListJobsRequest request;
        request.set_label(req.get_param_value("label"));
        pb::ListJobsResponse jobs;
        if (grpc::Status s = api_.list(request, jobs); !s.ok()) return sendStatus(res, s);
        res.set_header("Cache-Control", "no-store");
        sendJson(res, jobs);
    });
    // A .glb as the raw body, written to the store as it arrives (UploadScene's staging): the
    // answer's upload_id names it in a job's scene.
    server_->Post("/api/uploads", [this](const httplib::Request& req, httplib::Response& res,
                                         const httplib::ContentReader& content) {
        pb::UploadHeader header;
        header.set_format(pb::SCENE_FORMAT_GLB);
        header.set_scene_bytes(int64_t(contentLength(req)));
        std::unique_ptr<UploadWriter> writer;
        grpc::Status s = api_.beginUpload(header, writer);
        if (s.ok())
            content([&](const char* data, size_t size) {
                s = writer->append(std::string(data, size));
                return s.ok();
            });
        pb::UploadSceneResponse uploaded;
        if (s.ok()) s = writer->finish(uploaded);
        writer.reset();
        if (!s.ok()) {
            spdlog::info("dashboard: upload refused from {}: {}", req.remote_addr,
                         s.error_message());
            return sendStatus(res, s);
        }
        sendJson(res, uploaded, 201);
    });
    server_->Post("/api/jobs", [this](const httplib::Request& req, httplib::Response& res) {
        pb::JobSpec spec;
        pb::Job job;
        grpc::Status s = fromJson(req.body, spec);
        if (s.ok()) s = api_.submit(spec, job);
        if (!s.ok()) {
            spdlog::info("dashboard: submit refused from {}: {}", req.remote_addr,
                         s.error_message());
            return sendStatus(res, s);
        }
        spdlog::info("dashboard: {} submitted from {}", job.id(), req.remote_addr);
        sendJson(res, job, 201);
    });
    server_->Get(R"(/api/jobs/([^/]+))",
                 [this](const httplib::Request& req, httplib::Response& res) {
                     pb::Job job;
                     if (grpc::Status s = api_.get(req.matches[1].str(), job); !s.ok())
                         return sendStatus(res, s);
                     res.set_header("Cache-Control", "no-store");
                     sendJson(res, job);
                 });
    server_->Post(R"(/api/jobs/([^/]+)/cancel)",
                  [this](const httplib::Request& req, httplib::Response& res) {
                      pb::Job job;
                      if (grpc::Status s = api_.cancel(req.matches[1].str(), job); !s.ok())
                          return sendStatus(res, s);
                      sendJson(res, job);
                  });
    server_->Delete(R"(/api/jobs/([^/]+))",
                    [this](const httplib::Request& req, httplib::Response& res) {
                        if (grpc::Status s = api_.remove(req.matches[1].str()); !s.ok())
                            return sendStatus(res, s);
                        res.status = 204;
                    });
}

void DashboardServer::addEventRoute() {
    server_->Get(
        R"(/api/jobs/([^/]+)/events)", [this](const httplib::Request& req, httplib::Response& res) {
            std::shared_ptr<Job> job = api_.find(req.matches[1].str());
            if (!job) return sendStatus(res, unknownJob(req.matches[1].str()));
            if (openStreams_.fetch_add(1) >= options_.maxEventStreams) {
                openStreams_.fetch_sub(1);
                return sendStatus(
                    res, {grpc::StatusCode::RESOURCE_EXHAUSTED,
                          "the dashboard already has " + std::to_string(options_.maxEventStreams) +
                              " open event streams, its limit"});
            }
            auto stream = std::make_shared<JobEventStream>();
            bool previews = req.get_param_value("previews") != "0";
            if (grpc::Status s = job->addWatcher(stream, previews, api_.limits().maxWatchersPerJob);
                !s.ok()) {
                job->removeWatcher(stream.get());
                openStreams_.fetch_sub(1);
                return sendStatus(res, s);
            }
            res.set_header("Cache-Control", "no-store");
            auto lastWrite = std::make_shared<std::chrono::steady_clock::time_point>(
                std::chrono::steady_clock::now());
            res.set_chunked_content_provider(
                "text/event-stream",
                [this, stream, lastWrite](size_t, httplib::DataSink& sink) {
                    JobEventStream::Event event;
                    switch (stream->next(kEventWait, event)) {
                        case JobEventStream::Next::Event: {
                            std::string text = sseEvent(event);
                            *lastWrite = std::chrono::steady_clock::now();
                            return sink.write(text.data(), text.size());
                        }
                        case JobEventStream::Next::Timeout:
                            if (stopping_) break;
                            if (std::chrono::steady_clock::now() - *lastWrite < kKeepAlive)
                                return true;
                            *lastWrite = std::chrono::steady_clock::now();
                            return sink.write(": keep-alive\n\n", 15);
                        case JobEventStream::Next::End:
                            break;
                    }
                    sink.done();
                    return true;
                },
                [this, job, stream, peer = req.remote_addr](bool complete) {
                    if (!complete)
                        spdlog::info(
                            "dashboard: {} event stream to {} dropped (it stopped "
                            "reading or went away)",
                            job->tag(), peer);
                    job->removeWatcher(stream.get());
                    openStreams_.fetch_sub(1);
                });
        });
}

void DashboardServer::addResultRoute() {
    server_->Get(R"(/api/jobs/([^/]+)/(result\.exr|preview\.png|metadata\.json))",
                 [this](const httplib::Request& req, httplib::Response& res) {
                     std::string id = req.matches[1].str(), name = req.matches[2].str();
                     pb::ResultKind kind = name == "result.exr"    ? pb::RESULT_KIND_EXR
                                           : name == "preview.png" ? pb::RESULT_KIND_PNG
                                                                   : pb::RESULT_KIND_METADATA;
                     fs::path file;
                     if (grpc::Status s = api_.resultFile(id, kind, file); !s.ok())
                         return sendStatus(res, s);
                     auto in = std::make_shared<std::ifstream>(file, std::ios::binary);
                     std::error_code ec;
                     uint64_t size = fs::file_size(file, ec);
                     if (!*in || ec)
                         return sendStatus(res, {grpc::StatusCode::INTERNAL,
                                                 "job " + id + "'s " + name + " cannot be read"});
                     const char* type = kind == pb::RESULT_KIND_EXR   ? "image/x-exr"
                                        : kind == pb::RESULT_KIND_PNG ? "image/png"
                                                                      : "application/json";
                     res.set_header("Content-Disposition",
                                    "attachment; filename=\"" + id + "-" + name + "\"");
                     res.set_content_provider(
                         size, type, [in](size_t offset, size_t length, httplib::DataSink& sink) {
                             std::vector<char> buffer(std::min(length, kFileChunk));
                             in->seekg(std::streamoff(offset));
                             in->read(buffer.data(), std::streamsize(buffer.size()));
                             if (in->gcount() <= 0) return false;
                             return sink.write(buffer.data(), size_t(in->gcount()));
                         });
                 });
}

}  // namespace partita::server::dashboard
