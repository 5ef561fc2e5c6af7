#include "job_api.h"

#include "algorithm.h"
#include "job_memory.h"
#include "job_runner.h"
#include "parameter_wire.h"
#include "text.h"
#include "validation.h"

#ifndef PARTITA_VERSION
#define PARTITA_VERSION "0.0.0"
#endif

namespace partita::server {

namespace {

pb::BudgetKind toProto(BudgetKind k) {
    switch (k) {
        case BudgetKind::SamplesPerPixel:
            return pb::BUDGET_KIND_SAMPLES_PER_PIXEL;
        case BudgetKind::MutationsPerPixel:
            return pb::BUDGET_KIND_MUTATIONS_PER_PIXEL;
        case BudgetKind::Seconds:
            return pb::BUDGET_KIND_SECONDS;
    }
    return pb::BUDGET_KIND_UNSPECIFIED;
}

void fillLimits(const ServiceLimits& limits, pb::Limits& l) {
    l.set_max_width(limits.maxWidth);
    l.set_max_height(limits.maxHeight);
    l.set_max_samples_per_pixel(limits.maxSamplesPerPixel);
    l.set_max_seconds(limits.maxSeconds);
    l.set_max_upload_bytes(limits.maxUploadBytes);
    l.set_max_queued_jobs(limits.maxQueuedJobs);
    l.set_max_watchers_per_job(limits.maxWatchersPerJob);
    l.set_max_depth(limits.maxDepth);
    l.set_max_job_memory_bytes(limits.maxJobMemoryBytes);
    l.set_max_store_bytes(limits.maxStoreBytes);
    l.set_max_bootstrap_samples(limits.maxBootstrapSamples);
    l.set_max_raw_preview_bytes(limits.maxRawPreviewBytes);
    l.set_max_message_bytes(limits.maxMessageBytes);
    l.set_max_upload_streams(limits.maxUploadStreams);
    l.set_upload_ttl_seconds(limits.uploadTtlSeconds);
    l.set_max_receive_bytes(limits.maxReceiveBytes);
}

}  // namespace

grpc::Status unknownJob(const std::string& id) {
    return {grpc::StatusCode::NOT_FOUND, "no job '" + quoteInput(id) + "'"};
}

grpc::Status JobApi::submit(const pb::JobSpec& spec, pb::Job& out) {
    if (spec.scene().has_upload_id()) return submitStaged(spec, out);
    ValidatedSpec validated;
    if (grpc::Status s = validateJobSpec(spec, limits_, validated); !s.ok()) return s;
    if (spec.scene().has_scene_name()) {
        grpc::StatusCode code = grpc::StatusCode::OK;
        std::string error;
        if (scenes_.resolve(spec.scene().scene_name(), code, error).empty()) return {code, error};
    }
    if (grpc::Status s = checkEnvironmentImage(spec, scenes_, limits_, validated); !s.ok())
        return s;
    return jobs_.submit(spec, validated, out);
}

grpc::Status JobApi::submitStaged(const pb::JobSpec& spec, pb::Job& out) {
    if (!uploads_)
        return {grpc::StatusCode::INVALID_ARGUMENT,
                "this interface takes no upload ids: send the scene with the job"};
    std::shared_ptr<StagedUpload> staged;
    if (grpc::Status s = uploads_->find(spec.scene().upload_id(), staged); !s.ok()) return s;
    pb::JobSpec shaped = spec;
    *shaped.mutable_scene() = staged->shape();
    ValidatedSpec validated;
    if (grpc::Status s = settingsFromSpec(shaped, limits_, validated); !s.ok()) return s;
    auto read = [&](const std::string& uri) { return staged->readResource(uri); };
    if (grpc::Status s = checkEnvironmentImage(read, validated); !s.ok()) return s;
    return jobs_.submit(shaped, validated, out, staged.get());
}

grpc::Status JobApi::beginUpload(const pb::UploadHeader& header,
                                 std::unique_ptr<UploadWriter>& out) {
    if (!uploads_)
        return {grpc::StatusCode::UNIMPLEMENTED, "this interface takes no streamed uploads"};
    return uploads_->begin(header, out);
}

grpc::Status JobApi::get(const std::string& id, pb::Job& out) const {
    std::shared_ptr<Job> job = jobs_.find(id);
    if (!job) return unknownJob(id);
    out = job->snapshot();
    return grpc::Status::OK;
}

grpc::Status JobApi::list(const pb::ListJobsRequest& request, pb::ListJobsResponse& out) const {
    std::set<int> states;
    for (int state : request.states()) {
        if (!pb::JobState_IsValid(state) || state == pb::JOB_STATE_UNSPECIFIED)
            return {grpc::StatusCode::INVALID_ARGUMENT,
                    "unknown job state " + std::to_string(state)};
        states.insert(state);
    }
    for (auto& job : jobs_.list(request.label(), states)) *out.add_jobs() = std::move(job);
    return grpc::Status::OK;
}

grpc::Status JobApi::resultFile(const std::string& id, pb::ResultKind kind,
                                std::filesystem::path& file) const {
    std::shared_ptr<Job> job = jobs_.find(id);
    const char* name = kind == pb::RESULT_KIND_EXR        ? kResultExr
                       : kind == pb::RESULT_KIND_PNG      ? kResultPng
                       : kind == pb::RESULT_KIND_METADATA ? kResultMetadata
                                                          : nullptr;
    if (!job) return unknownJob(id);
    if (!name)
        return {
            grpc::StatusCode::INVALID_ARGUMENT,
            "unknown result kind " + std::to_string(int(kind)) + ": ask for EXR, PNG or METADATA"};
    if (pb::JobState state = job->state(); state != pb::JOB_STATE_DONE)
        return {grpc::StatusCode::FAILED_PRECONDITION, "job " + job->id() + " is " +
                                                           stateName(state) +
                                                           ": results exist only once it is DONE"};
    file = jobs_.resultDir(job->id()) / name;
    return grpc::Status::OK;
}

grpc::Status JobApi::checkRawPreviews(const Job& job) const {
    ValidatedSpec v;
    if (!settingsFromSpec(job.spec(), limits_, v).ok()) return grpc::Status::OK;  // it fails
    uint64_t bytes = rawPreviewBytes(v.algorithm, v.settings);
    if (bytes <= uint64_t(std::max<int64_t>(0, limits_.maxRawPreviewBytes)))
        return grpc::Status::OK;
    return {grpc::StatusCode::RESOURCE_EXHAUSTED,
            "raw previews of job " + job.id() + " would take " + humanBytes(double(bytes)) +
                " a frame (every layer as float32 RGB), over this server's limit of " +
                humanBytes(double(limits_.maxRawPreviewBytes)) +
                " (--max-raw-preview-mb): watch it without raw previews, or submit it with "
                "fewer layers"};
}

void JobApi::listScenes(pb::ListScenesResponse& out) const {
    for (const auto& entry : scenes_.list()) {
        pb::SceneInfo* info = out.add_scenes();
        info->set_name(entry.name);
        info->set_file(entry.file);
    }
}

void JobApi::serverInfo(pb::ServerInfo& out) const {
    registerBuiltinAlgorithms();
    out.set_version(PARTITA_VERSION);
    out.set_threads(jobs_.threads());
    out.set_max_concurrent_jobs(jobs_.maxJobs());
    fillLimits(limits_, *out.mutable_limits());
    const auto& registry = AlgorithmRegistry::instance();
    for (const auto& name : registry.names()) {
        const auto* entry = registry.find(name);
        pb::AlgorithmInfo* info = out.add_algorithms();
        info->set_name(entry->name);
        info->set_description(entry->description);
        info->set_native_budget(toProto(entry->nativeBudget));
        describeAlgorithmParameters(*entry, *info);
    }
}

}  // namespace partita::server
