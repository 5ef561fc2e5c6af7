#include "upload_staging.h"

#include <fcntl.h>
#include <google/protobuf/io/coded_stream.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <random>
#include <set>

#include "gltf/gltf_loader.h"
#include "gltf/resource_resolver.h"
#include "job_memory.h"
#include "text.h"
#include "validation.h"

namespace partita::server {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStagedFile = "upload.pb";
constexpr const char* kPartialFile = "upload.pb.part";

grpc::Status invalid(const std::string& m) { return {grpc::StatusCode::INVALID_ARGUMENT, m}; }

/// Protobuf's encoding of a length-delimited field's start: its tag, then the length.
std::string fieldStart(int field, uint64_t length) {
    using google::protobuf::io::CodedOutputStream;
    uint8_t buffer[2 * 10];
    uint8_t* end = CodedOutputStream::WriteVarint32ToArray(uint32_t(field << 3 | 2), buffer);
    end = CodedOutputStream::WriteVarint64ToArray(length, end);
    return std::string(reinterpret_cast<char*>(buffer), size_t(end - buffer));
}

/// Bytes of a length-delimited field holding `length` bytes (fields 1-15: a one-byte tag).
uint64_t fieldBytes(uint64_t length) {
    return 1 + google::protobuf::io::CodedOutputStream::VarintSize64(length) + length;
}

grpc::Status checkHeader(const pb::UploadHeader& h, const ServiceLimits& limits, uint64_t& total) {
    if (h.format() != pb::SCENE_FORMAT_GLB && h.format() != pb::SCENE_FORMAT_GLTF)
        return invalid("the upload's header must say its format: SCENE_FORMAT_GLB or _GLTF (got " +
                       std::to_string(int(h.format())) + ")");
    if (h.scene_bytes() <= 0) return invalid("the uploaded scene file is empty");
    if (h.format() == pb::SCENE_FORMAT_GLB && h.resources_size() > 0)
        return invalid("a .glb is uploaded alone: it has no resources");
    total = uint64_t(h.scene_bytes());
    std::set<std::string> seen;
    for (const auto& r : h.resources()) {
        if (grpc::Status s = checkUploadedUri(r.uri(), seen); !s.ok()) return s;
        if (r.size() < 0)
            return invalid("resource '" + printableUri(r.uri()) + "' has a negative size");
        total += uint64_t(r.size()) + r.uri().size();  // as SceneSource::uploadBytes counts
    }
    return checkUploadSize(total, limits);
}

}  // namespace

bool isUploadId(const std::string& id) {
    return id.size() == 16 && std::all_of(id.begin(), id.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
           });
}

// ----- StagedUpload --------------------------------------------------------------------------

StagedUpload::StagedUpload(std::string id, fs::path file, pb::SceneFormat format, uint64_t bytes,
                           std::vector<Resource> resources)
    : id_(std::move(id)),
      file_(std::move(file)),
      format_(format),
      bytes_(bytes),
      resources_(std::move(resources)) {}

StagedUpload::~StagedUpload() {
    std::error_code ec;
    fs::remove_all(file_.parent_path(), ec);
}

pb::SceneSource StagedUpload::shape() const {
    pb::SceneSource source;
    if (format_ == pb::SCENE_FORMAT_GLB) {
        source.set_glb("");
        return source;
    }
    pb::GltfUpload* gltf = source.mutable_gltf();
    for (const Resource& r : resources_) gltf->add_resources()->set_uri(r.uri);
    return source;
}

std::vector<uint8_t> StagedUpload::readResource(const std::string& uri) const {
    auto it = std::find_if(resources_.begin(), resources_.end(),
                           [&](const Resource& r) { return r.uri == uri; });
    if (it == resources_.end())
        throw SceneLoadError("no resource '" + quoteInput(uri, 64) +
                             "' was uploaded with the scene");
    std::vector<uint8_t> bytes(it->size);
    int fd = ::open(file_.c_str(), O_RDONLY | O_CLOEXEC);
    size_t got = 0;
    while (fd >= 0 && got < bytes.size()) {
        ssize_t n = ::pread(fd, bytes.data() + got, bytes.size() - got, off_t(it->offset + got));
        if (n <= 0) break;
        got += size_t(n);
    }
    if (fd >= 0) ::close(fd);
    if (got != bytes.size())
        throw SceneLoadError("the uploaded resource '" + quoteInput(uri, 64) +
                             "' cannot be read back");
    return bytes;
}

// ----- UploadWriter --------------------------------------------------------------------------

UploadWriter::UploadWriter(UploadStaging& staging, std::string id, const pb::UploadHeader& h,
                           uint64_t reserved)
    : staging_(staging), id_(std::move(id)), format_(h.format()), reserved_(reserved) {
    const uint64_t scene = uint64_t(h.scene_bytes());
    declared_ = reserved;  // checkHeader's total: every file and resource uri
    if (format_ == pb::SCENE_FORMAT_GLB) {
        segments_.push_back({fieldStart(pb::SceneSource::kGlbFieldNumber, scene), scene});
        return;
    }
    // SceneSource.gltf = GltfUpload{gltf = 1, resources = 2 (Resource{uri = 1, data = 2})}.
    uint64_t gltfMessage = fieldBytes(scene);
    std::vector<uint64_t> resourceMessages;
    for (const auto& r : h.resources()) {
        uint64_t m = fieldBytes(r.uri().size()) + fieldBytes(uint64_t(r.size()));
        resourceMessages.push_back(m);
        gltfMessage += fieldBytes(m);
    }
    segments_.push_back({fieldStart(pb::SceneSource::kGltfFieldNumber, gltfMessage) +
                             fieldStart(pb::GltfUpload::kGltfFieldNumber, scene),
                         scene});
    for (int i = 0; i < h.resources_size(); ++i) {
        const auto& r = h.resources(i);
        segments_.push_back(
            {fieldStart(pb::GltfUpload::kResourcesFieldNumber, resourceMessages[size_t(i)]) +
                 fieldStart(pb::Resource::kUriFieldNumber, r.uri().size()) + r.uri() +
                 fieldStart(pb::Resource::kDataFieldNumber, uint64_t(r.size())),
             uint64_t(r.size())});
        resources_.push_back({r.uri(), 0, uint64_t(r.size())});
    }
}

UploadWriter::~UploadWriter() {
    if (fd_ >= 0) ::close(fd_);
    if (!finished_) {
        std::error_code ec;
        fs::remove_all(staging_.folder(id_), ec);
    }
    staging_.ended(this, reserved_);
}

grpc::Status UploadWriter::openFile() {
    std::error_code ec;
    fs::create_directories(staging_.folder(id_), ec);
    fd_ = ::open((staging_.folder(id_) / kPartialFile).c_str(),
                 O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd_ < 0)
        return {grpc::StatusCode::INTERNAL,
                std::string("cannot stage the upload: ") + std::strerror(errno)};
    return grpc::Status::OK;
}

grpc::Status UploadWriter::write(const char* data, size_t size) {
    while (size > 0) {
        ssize_t n = ::write(fd_, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            return {grpc::StatusCode::INTERNAL,
                    std::string("cannot stage the upload: ") + std::strerror(errno)};
        data += n;
        size -= size_t(n);
        written_ += uint64_t(n);
    }
    return grpc::Status::OK;
}

grpc::Status UploadWriter::append(const std::string& data) {
    if (grpc::Status s = staging_.touch(*this); !s.ok()) return s;
    size_t at = 0;
    for (;;) {
        const bool more = at < data.size();
        if (leftInSegment_ == 0 && segment_ < segments_.size() &&
            (more || segments_[segment_].size == 0)) {
            // The next file starts (an empty one at once): its field prefix goes first.
            const Segment& next = segments_[segment_];
            if (grpc::Status s = write(next.prefix.data(), next.prefix.size()); !s.ok()) return s;
            if (segment_ > 0) resources_[segment_ - 1].offset = written_;
            leftInSegment_ = next.size;
            ++segment_;
            continue;
        }
        if (!more) return grpc::Status::OK;
        if (leftInSegment_ == 0)
            return invalid("the upload sent more bytes than its header declared (" +
                           std::to_string(declared_) + ")");
        size_t n = size_t(std::min<uint64_t>(leftInSegment_, data.size() - at));
        if (grpc::Status s = write(data.data() + at, n); !s.ok()) return s;
        at += n;
        leftInSegment_ -= n;
    }
}

grpc::Status UploadWriter::finish(pb::UploadSceneResponse& out) {
    // Trailing empty resources have no bytes to wait for: write their prefixes.
    if (grpc::Status s = append(""); !s.ok()) return s;
    if (grpc::Status s = staging_.touch(*this, true); !s.ok()) return s;
    if (leftInSegment_ > 0 || segment_ < segments_.size())
        return invalid("the upload ended before all the bytes its header declared (" +
                       std::to_string(declared_) + ") arrived");
    if (::fsync(fd_) != 0)
        return {grpc::StatusCode::INTERNAL,
                std::string("cannot stage the upload: ") + std::strerror(errno)};
    ::close(fd_);
    fd_ = -1;
    const fs::path file = staging_.folder(id_) / kStagedFile;
    std::error_code ec;
    fs::rename(staging_.folder(id_) / kPartialFile, file, ec);
    if (ec) return {grpc::StatusCode::INTERNAL, "cannot stage the upload: " + ec.message()};
    finished_ = true;
    staging_.publish(
        std::make_shared<StagedUpload>(id_, file, format_, declared_, std::move(resources_)));
    out.set_upload_id(id_);
    out.set_bytes(int64_t(declared_));
    return grpc::Status::OK;
}

// ----- UploadStaging -------------------------------------------------------------------------

UploadStaging::UploadStaging(const fs::path& storeDir, const ServiceLimits& limits, Reserve reserve,
                             Release release)
    : dir_(storeDir / "uploads"),
      limits_(limits),
      reserve_(std::move(reserve)),
      release_(std::move(release)) {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    fs::create_directories(dir_, ec);
}

std::string UploadStaging::newId() {
    static std::mt19937_64 rng(std::random_device{}());
    for (;;) {
        char buf[17];
        std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(rng()));
        std::error_code ec;
        if (!staged_.count(buf) && !fs::exists(folder(buf), ec)) return buf;
    }
}

grpc::Status UploadStaging::begin(const pb::UploadHeader& header,
                                  std::unique_ptr<UploadWriter>& out) {
    uint64_t total = 0;
    if (grpc::Status s = checkHeader(header, limits_, total); !s.ok()) return s;
    std::string id;
    std::vector<std::pair<std::string, uint64_t>> freed;
    const auto now = std::chrono::steady_clock::now();
    grpc::Status admitted = grpc::Status::OK;
    {
        std::lock_guard lock(mutex_);
        expireLocked(now);
        if (inFlight_ >= limits_.maxUploadStreams) reclaimIdleLocked(now, freed);
        if (inFlight_ >= limits_.maxUploadStreams)
            admitted = {grpc::StatusCode::RESOURCE_EXHAUSTED,
                        "this server is already receiving " + std::to_string(inFlight_) +
                            " uploads, its limit (--max-upload-streams); try again when one ends"};
        else
            ++inFlight_, id = newId();
    }
    for (const auto& [idle, reserved] : freed) {
        spdlog::warn("upload {} dropped: nothing received for {} s while another waited", idle,
                     limits_.uploadIdleSeconds);
        if (reserved > 0) release_(reserved);
        std::error_code ec;
        fs::remove_all(folder(idle), ec);
    }
    if (!admitted.ok()) return admitted;
    if (grpc::Status s = reserve_(total); !s.ok()) {
        ended(nullptr, 0);
        return s;
    }
    out.reset(new UploadWriter(*this, id, header, total));
    {
        std::lock_guard lock(mutex_);
        out->lastActivity_ = now;
        active_.insert(out.get());
    }
    // The file exists from admission on: an upload in flight is visible in the store.
    if (grpc::Status s = out->openFile(); !s.ok()) {
        out.reset();
        return s;
    }
    return grpc::Status::OK;
}

void UploadStaging::reclaimIdleLocked(std::chrono::steady_clock::time_point now,
                                      std::vector<std::pair<std::string, uint64_t>>& freed) {
    const auto idle = std::chrono::duration<double>(limits_.uploadIdleSeconds);
    for (auto it = active_.begin(); it != active_.end();) {
        UploadWriter* w = *it;
        if (w->finishing_ || now - w->lastActivity_ < idle) {
            ++it;
            continue;
        }
        w->abandoned_ = true;
        freed.emplace_back(w->id_, w->reserved_);
        it = active_.erase(it);
        --inFlight_;
    }
}

grpc::Status UploadStaging::touch(UploadWriter& writer, bool finishing) {
    std::lock_guard lock(mutex_);
    if (writer.abandoned_)
        return {grpc::StatusCode::ABORTED,
                "this upload sent nothing for " + fmt::format("{}", limits_.uploadIdleSeconds) +
                    " s while another waited for its place (--upload-idle-seconds): it was "
                    "dropped; upload the scene again"};
    writer.lastActivity_ = std::chrono::steady_clock::now();
    writer.finishing_ = writer.finishing_ || finishing;
    return grpc::Status::OK;
}

void UploadStaging::ended(UploadWriter* writer, uint64_t reserved) {
    {
        std::lock_guard lock(mutex_);
        if (writer && writer->abandoned_) return;  // its place and bytes were given back then
        if (writer) active_.erase(writer);
        --inFlight_;
    }
    if (reserved > 0) release_(reserved);
}

void UploadStaging::publish(std::shared_ptr<StagedUpload> upload) {
    spdlog::info("upload {} staged: {}", upload->id(), humanBytes(double(upload->bytes())));
    std::lock_guard lock(mutex_);
    const std::string id = upload->id();
    staged_[id] = {std::move(upload), std::chrono::steady_clock::now()};
}

void UploadStaging::expireLocked(std::chrono::steady_clock::time_point now) {
    const auto ttl = std::chrono::duration<double>(limits_.uploadTtlSeconds);
    for (auto it = staged_.begin(); it != staged_.end();) {
        if (now - it->second.lastUsed < ttl) {
            ++it;
            continue;
        }
        spdlog::info("upload {} removed: no job named it for {} s", it->first,
                     limits_.uploadTtlSeconds);
        it = staged_.erase(it);  // the folder goes with the last holder
    }
}

grpc::Status UploadStaging::find(const std::string& id, std::shared_ptr<StagedUpload>& out) {
    std::lock_guard lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    expireLocked(now);
    auto it = isUploadId(id) ? staged_.find(id) : staged_.end();
    if (it == staged_.end())
        return {grpc::StatusCode::NOT_FOUND,
                "no upload '" + quoteInput(id, 64) +
                    "': it was never finished, it expired (unused for " +
                    fmt::format("{}", limits_.uploadTtlSeconds) +
                    " s), or partitad restarted since; upload the scene again"};
    it->second.lastUsed = now;
    out = it->second.upload;
    return grpc::Status::OK;
}

size_t UploadStaging::stagedCount() const {
    std::lock_guard lock(mutex_);
    return staged_.size();
}

}  // namespace partita::server
