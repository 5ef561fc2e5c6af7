#include "job_runner.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <fstream>
#include <new>
#include <nlohmann/json.hpp>
#include <sstream>

#include "image_io.h"
#include "params/job_parameters.h"
#include "render_scene.h"
#include "renderer.h"
#include "scene_environment.h"
#include "slurm_shards.h"
#include "text.h"
#include "validation.h"

namespace partita::server {

namespace fs = std::filesystem;

namespace {

/// Thrown between the loading steps when the job was cancelled.
struct CancelledWhileLoading {};

/// The job state of an algorithm's progress phase: "prepass" and mlt's "bootstrap" (the BDPT
/// samples that give b and the chains' starts) are pre-passes, "render" is rendering; other
/// phases leave the state as it is.
pb::JobState stateOfPhase(const std::string& phase) {
    if (phase == "prepass" || phase == "bootstrap") return pb::JOB_STATE_PREPASS;
    if (phase == "render") return pb::JOB_STATE_RENDERING;
    return pb::JOB_STATE_UNSPECIFIED;
}

/// Maps the algorithm's progress phases to job states and forwards progress and previews.
class JobObserver : public RenderObserver {
  public:
    JobObserver(Job& job, const Job::Persist& persist) : job_(job), persist_(persist) {}

    void onProgress(const RenderProgress& p) override {
        pb::JobState target = stateOfPhase(p.phase);
        if (target != pb::JOB_STATE_UNSPECIFIED) advance(target);
        job_.publishProgress(p);
    }

    void onPreview(LayeredImage image, const RenderStats&) override {
        job_.publishFrame(std::move(image), false);
    }
    /// Previews are made while someone watches them (a watcher that joins gets the next one).
    bool wantsPreviews() const override { return job_.hasPreviewWatchers(); }
    double previewDeliverySeconds() const override { return job_.previewEncodeSeconds(); }

    /// Moves forward to `state` (no-op when already there or past it).
    void advance(pb::JobState state) {
        try {
            if (job_.transition(state, "", persist_))
                spdlog::info("{} {}", job_.tag(),
                             state == pb::JOB_STATE_PREPASS ? "pre-pass" : "rendering");
        } catch (const std::exception& e) {
            // The render goes on; the state is recorded at the next transition that succeeds.
            spdlog::error("{} could not record state {}: {}", job_.tag(), stateName(state),
                          e.what());
        }
    }

  private:
    Job& job_;
    const Job::Persist& persist_;
};

/// The scene uploaded with `job`, as stored in its folder.
pb::SceneSource readUpload(const Job& job, const RunContext& ctx) {
    std::ifstream in(ctx.store.jobDir(job.id()) / kUploadFile, std::ios::binary);
    if (!in) throw std::runtime_error("the uploaded scene of this job is missing from the store");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    pb::SceneSource upload;
    if (!upload.ParseFromString(bytes.str()))
        throw std::runtime_error("the uploaded scene of this job is damaged in the store");
    return upload;
}

SceneData loadScene(const Job& job, const RunContext& ctx) {
    const pb::SceneSource& source = job.spec().scene();
    if (source.has_scene_name()) return ctx.scenes.loadNamed(source.scene_name());
    return SceneSource::loadUpload(readUpload(job, ctx), uint64_t(ctx.limits.maxUploadBytes));
}

/// The job's environment on the scene. An image (a resource of the upload, or a file in the
/// named scene's folder) is written into the job's folder for OpenImageIO to read, then removed.
void attachJobEnvironment(const Job& job, const RunContext& ctx, const EnvironmentSettings& env,
                          SceneData& data) {
    if (env.file.empty()) {
        attachEnvironment(data, env);
        return;
    }
    const pb::SceneSource& source = job.spec().scene();
    std::vector<uint8_t> bytes;
    try {
        if (source.has_scene_name()) {
            bytes = ctx.scenes.readNamedResource(source.scene_name(), env.file,
                                                 uint64_t(ctx.limits.maxUploadBytes));
        } else {
            bytes = SceneSource::readUploadedResource(readUpload(job, ctx), env.file);
        }
    } catch (const std::exception& e) {
        throw std::runtime_error(std::string("environment image: ") + e.what());
    }
    // A named scene's job has no folder of its own until now (issue #25 5).
    std::error_code dirError;
    fs::create_directories(ctx.store.jobDir(job.id()), dirError);
    fs::path local =
        ctx.store.jobDir(job.id()) / ("environment" + fs::path(env.file).extension().string());
    {
        std::ofstream out(local, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        if (!out) throw std::runtime_error("cannot write the environment image into the store");
    }
    EnvironmentSettings onDisk = env;
    onDisk.file = local.string();
    try {
        attachEnvironment(data, onDisk);
    } catch (const std::exception& e) {
        std::error_code ec;
        fs::remove(local, ec);
        // The message names the job's image, not the store's copy of it (a server path).
        std::string why = e.what();
        for (size_t at; (at = why.find(local.string())) != std::string::npos;)
            why.replace(at, local.string().size(), env.file);
        throw std::invalid_argument(why);
    }
    std::error_code ec;
    fs::remove(local, ec);
}

/// A parameter's value as JSON: numbers as numbers (a float field's as the shortest decimal
/// that reads back as it: 0.01, not 0.009999999776), text as text, an RGB as three numbers.
nlohmann::ordered_json parameterJson(const ParameterSpec& spec, const ParameterValue& value) {
    auto real = [&](double v) {
        return spec.singlePrecision ? std::stod(fmt::format("{}", float(v))) : v;
    };
    return std::visit(
        [&](const auto& v) -> nlohmann::ordered_json {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::monostate>)
                return nullptr;
            else if constexpr (std::is_same_v<T, double>)
                return real(v);
            else if constexpr (std::is_same_v<T, RgbValue>)
                return {real(v[0]), real(v[1]), real(v[2])};
            else
                return v;
        },
        value);
}

std::string metadataJson(const Job& job, const ValidatedSpec& v, const RenderResult& result) {
    const RenderSettings& s = v.settings;
    pb::Job record = job.snapshot();
    nlohmann::ordered_json j;
    j["job_id"] = job.id();
    j["label"] = job.spec().label();
    j["scene"] = sceneLabel(job.spec());
    j["algorithm"] = v.algorithm;
    // Every declared parameter as the job ran it (defaults filled in; an unset one is absent),
    // then the budget and the priority.
    nlohmann::ordered_json parameters = nlohmann::ordered_json::object();
    for (const JobParameter& p : jobParameters(registeredAlgorithm(v.algorithm), s))
        if (!std::holds_alternative<std::monostate>(p.value))
            parameters[p.spec->name] = parameterJson(*p.spec, p.value);
    parameters["budget_kind"] = budgetKindName(s.budgetKind);
    parameters["budget"] = s.budget;
    parameters["priority"] = job.spec().priority();
    j["parameters"] = parameters;
    nlohmann::ordered_json stats = nlohmann::ordered_json::object();
    for (const auto& [k, value] : result.stats.values) stats[k] = value;
    j["stats"] = stats;
    nlohmann::ordered_json labels = nlohmann::ordered_json::object();
    for (const auto& [k, value] : result.stats.labels) labels[k] = value;
    j["labels"] = labels;
    nlohmann::ordered_json layers = nlohmann::ordered_json::array();
    for (const auto& l : result.image.layers) layers.push_back(l.name);
    j["layers"] = layers;
    j["created_unix_ms"] = record.created_unix_ms();
    j["started_unix_ms"] = record.started_unix_ms();
    j["written_unix_ms"] = nowUnixMs();
    j["render"] = describeRender(v.algorithm, s, result.stats);
    return j.dump(2) + "\n";
}

void writeResults(const Job& job, const RunContext& ctx, const ValidatedSpec& v,
                  const RenderResult& result) {
    fs::path dir = ctx.store.jobDir(job.id());
    fs::create_directories(dir);
    auto attributes = describeRender(v.algorithm, v.settings, result.stats);
    attributes["partita:job_id"] = job.id();
    writeExr(dir / kResultExr, result.image, attributes);
    writePng(dir / kResultPng, result.image.combined, autoExposure(result.image.combined));
    JobStore::writeFileAtomic(dir / kResultMetadata, metadataJson(job, v, result));
}

/// The folder of a job's Slurm shards, plan and logs.
fs::path slurmDir(const RunContext& ctx, const Job& job) {
    return ctx.store.jobDir(job.id()) / "slurm";
}

/// The scene file the shards of `job` read, or "" (with `why`) when the job renders here
/// instead: a time budget cannot be sharded; an environment image and an uploaded .gltf with
/// its resources would have to be written out for the tasks (not done yet). An uploaded .glb is
/// written into the job's folder.
std::string shardScenePath(const Job& job, const RunContext& ctx, const ValidatedSpec& v,
                           std::string& why) {
    if (v.settings.budgetKind == BudgetKind::Seconds) {
        why = "a time budget is not reproducible across machines";
        return {};
    }
    if (!v.settings.environment.file.empty()) {
        why = "environment images are not yet passed to the shards";
        return {};
    }
    const pb::SceneSource& source = job.spec().scene();
    if (source.has_scene_name()) {
        grpc::StatusCode code;
        std::string error;
        fs::path path = ctx.scenes.resolve(source.scene_name(), code, error);
        if (path.empty()) throw std::runtime_error(error);
        return fs::absolute(path).string();
    }
    const pb::SceneSource upload = readUpload(job, ctx);
    if (!upload.has_glb()) {
        why = "uploaded .gltf scenes with resources are not yet written out for the shards";
        return {};
    }
    fs::path file = slurmDir(ctx, job) / "scene.glb";
    fs::create_directories(file.parent_path());
    JobStore::writeFileAtomic(file, upload.glb());
    return fs::absolute(file).string();
}

/// Renders the job here, or as shards of a Slurm array under --executor slurm when it can be.
RenderResult renderJob(Job& job, const RunContext& ctx, const ValidatedSpec& v,
                       const RenderScene& scene, JobObserver& observer) {
    std::string why;
    const std::string scenePath = ctx.cluster.slurm() ? shardScenePath(job, ctx, v, why) : "";
    if (scenePath.empty()) {
        if (!why.empty()) spdlog::info("{} renders here, not on Slurm: {}", job.tag(), why);
        RenderResult result =
            runRender(scene, v.algorithm, v.settings, ctx.pool, job.cancelFlag(), observer);
        if (!why.empty()) result.stats.labels["executor"] = "local: " + why;
        return result;
    }
    SlurmJob slurm{ctx.cluster,
                   slurmDir(ctx, job),
                   "partita-" + job.id(),
                   job.tag(),
                   v.algorithm,
                   v.settings,
                   scenePath,
                   [&job] { return job.cancelReason() == CancelReason::Shutdown; }};
    RenderResult result = renderOnSlurm(slurm, {scene, ctx.pool, job.cancelFlag(), observer});
    result.stats.labels["executor"] = "slurm";
    return result;
}

/// Ends a job that did not finish: FAILED with `error`, or (error empty) cancelled or re-queued.
void endUnfinished(Job& job, const Job::Persist& persist, const std::string& error) {
    try {
        if (!error.empty()) {
            job.transition(pb::JOB_STATE_FAILED, error, persist);
            spdlog::warn("{} failed: {}", job.tag(), error);
        } else if (job.cancelReason() == CancelReason::Shutdown) {
            std::string note =
                "re-queued: partitad stopped while the job was " + stateName(job.state());
            pb::Job record = job.snapshot();
            std::map<std::string, double> stats(record.stats().begin(), record.stats().end());
            stats["requeued"] += 1;
            if (job.transition(pb::JOB_STATE_QUEUED, "", persist, note, &stats))
                spdlog::info("{} re-queued (daemon shutting down); it runs again after restart",
                             job.tag());
        } else {
            job.transition(pb::JOB_STATE_CANCELLED, "", persist, "cancelled by a client");
            spdlog::info("{} cancelled", job.tag());
        }
    } catch (const std::exception& e) {
        spdlog::error("{} could not record its end: {}", job.tag(), e.what());
    }
}

}  // namespace

void removeUpload(const JobStore& store, const std::string& id) {
    std::error_code ec;
    fs::remove(store.jobDir(id) / kUploadFile, ec);
}

void runJob(Job& job, const RunContext& ctx, const Job::Persist& persist) {
    auto started = std::chrono::steady_clock::now();
    auto checkCancel = [&] {
        if (job.cancelRequested()) throw CancelledWhileLoading{};
    };
    try {
        checkCancel();
        if (!job.transition(pb::JOB_STATE_LOADING, "", persist)) return;
        spdlog::info("{} loading scene '{}'", job.tag(), quoteInput(sceneLabel(job.spec()), 200));
        ValidatedSpec v;
        if (grpc::Status s = settingsFromSpec(job.spec(), ctx.limits, v); !s.ok())
            throw std::runtime_error(s.error_message());
        SceneData data = loadScene(job, ctx);
        for (const auto& w : data.warnings) spdlog::warn("{} scene: {}", job.tag(), w);
        attachJobEnvironment(job, ctx, v.settings.environment, data);
        checkCancel();
        RenderScene scene(std::move(data));
        checkCancel();

        JobObserver observer(job, persist);
        RenderResult result = renderJob(job, ctx, v, scene, observer);
        job.releasePreviewFrame();
        writeResults(job, ctx, v, result);
        double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        std::map<std::string, double> stats = result.stats.values;
        stats["job_seconds"] = seconds;
        if (auto before = job.snapshot(); before.stats().count("requeued"))
            stats["requeued"] = before.stats().at("requeued");
        job.publishFrame(std::move(result.image), true);
        observer.advance(pb::JOB_STATE_RENDERING);
        // A warning of the render (a scene without any light renders black) reaches watchers
        // and listings as the job's note.
        auto warning = result.stats.labels.find("warning");
        job.transition(pb::JOB_STATE_DONE, "", persist,
                       warning == result.stats.labels.end() ? "" : warning->second, &stats);
        job.keepFinalFrameOnDisk(ctx.store.jobDir(job.id()) / kResultExr);
        spdlog::info("{} done in {:.2f} s", job.tag(), seconds);
    } catch (const RenderCancelled&) {
        endUnfinished(job, persist, "");
    } catch (const CancelledWhileLoading&) {
        endUnfinished(job, persist, "");
    } catch (const std::bad_alloc&) {
        endUnfinished(job, persist, "out of memory");
    } catch (const std::exception& e) {
        std::string msg = e.what();
        endUnfinished(job, persist, msg.empty() ? "unknown error" : msg);
    }
    if (isTerminal(job.state())) {
        removeUpload(ctx.store, job.id());
        removeSlurmFiles(slurmDir(ctx, job));
    }
}

}  // namespace partita::server
