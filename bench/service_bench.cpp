#include "service_bench.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

#include "cli/connection.h"
#include "cli/private_daemon.h"
#include "cli/proto.h"
#include "cli/scene_source.h"
#include "gltf/gltf_loader.h"
#include "render_scene.h"
#include "renderer.h"
#include "thread_pool.h"

namespace partita::eval {

namespace {

namespace pb = ::partita::v1;
using Clock = std::chrono::steady_clock;

constexpr const char* kRenderLabel = "partita-eval service render";
constexpr const char* kTinyLabel = "partita-eval service submit";

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// One render's times, in seconds. `algorithm` is the render statistic "seconds" (first pass to
/// final image: previews included); `passes` is "render_seconds" (the sampling passes only);
/// `wall` is end to end: in-process scene load + BVH + render, through the daemon SubmitJob
/// (with the scene upload) until the watcher receives DONE.
struct RunTimes {
    double algorithm = 0, passes = 0, wall = 0;
    // Process CPU seconds during the passes ("render_cpu_seconds"): in the daemon this also
    // counts its other threads (PNG encoding of previews, gRPC) competing for the cores.
    double passesCpu = 0;
};

/// What the watcher saw of one daemon job.
struct DaemonRun {
    RunTimes times;
    double firstPreviewMs = -1;                // after SubmitJob was called
    double firstPreviewAfterRenderingMs = -1;  // after the RENDERING state event arrived
    bool firstPreviewFinal = false;
    int previews = 0, progressEvents = 0;
    double previewBytes = 0;  // PNG bytes received
};

// ----- in-process ----------------------------------------------------------------------------

RunTimes renderInProcess(const ServiceOptions& o, ThreadPool& pool) {
    RenderSettings s;
    s.width = o.width;
    s.height = o.height;
    s.budgetKind = BudgetKind::SamplesPerPixel;
    s.budget = o.spp;
    s.seed = o.seed;
    s.maxDepth = o.maxDepth;
    // The baseline is the bare core: no previews at all (pass sizes do not depend on this).
    s.previewIntervalSeconds = 0;
    auto start = Clock::now();
    RenderScene scene(loadGltfFile(o.scene));
    std::atomic<bool> cancel{false};
    RenderObserver quiet;
    RenderResult res = runRender(scene, "pt", s, pool, cancel, quiet);
    return {res.stats.values["seconds"], res.stats.values["render_seconds"], secondsSince(start),
            res.stats.values["render_cpu_seconds"]};
}

// ----- through the daemon --------------------------------------------------------------------

pb::JobSpec renderSpec(const ServiceOptions& o, const pb::SceneSource& scene) {
    pb::JobSpec spec;
    *spec.mutable_scene() = scene;
    spec.set_width(o.width);
    spec.set_height(o.height);
    spec.set_algorithm("pt");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SAMPLES_PER_PIXEL);
    spec.mutable_budget()->set_amount(o.spp);
    spec.set_seed(o.seed);
    spec.set_max_depth(o.maxDepth);
    spec.set_preview_interval_seconds(o.previewInterval);
    spec.set_label(kRenderLabel);
    return spec;
}

pb::JobSpec tinySpec(const ServiceOptions& o) {
    pb::JobSpec spec;
    spec.mutable_scene()->set_scene_name(o.smallScene);
    spec.set_width(16);
    spec.set_height(16);
    spec.set_algorithm("pt");
    spec.mutable_budget()->set_kind(pb::BUDGET_KIND_SAMPLES_PER_PIXEL);
    spec.mutable_budget()->set_amount(1);
    spec.set_label(kTinyLabel);
    return spec;
}

bool isTerminal(pb::JobState s) {
    return s == pb::JOB_STATE_DONE || s == pb::JOB_STATE_FAILED || s == pb::JOB_STATE_CANCELLED;
}

double statOf(const pb::Job& job, const std::string& name) {
    auto it = job.stats().find(name);
    if (it == job.stats().end())
        throw std::runtime_error("job " + job.id() + " reports no statistic '" + name + "'");
    return it->second;
}

void deleteJob(cli::Connection& c, const std::string& id) {
    pb::DeleteJobRequest request;
    request.set_job_id(id);
    c.call(&pb::Partita::Stub::DeleteJob, request, "delete job " + id);
}

void notePreview(DaemonRun& run, const pb::PreviewFrame& frame, double ms, double renderingMs) {
    if (run.previews++ == 0) {
        run.firstPreviewMs = ms;
        run.firstPreviewAfterRenderingMs = renderingMs >= 0 ? ms - renderingMs : -1;
        run.firstPreviewFinal = frame.final();
    }
    for (const auto& layer : frame.layers()) run.previewBytes += double(layer.png().size());
}

/// Streams the job's events with PNG previews (what `partita render --previews DIR` asks for)
/// until its final state; returns it. Times are taken when each event is read.
pb::Job watchToEnd(cli::Connection& c, const std::string& id, Clock::time_point submitted,
                   DaemonRun& run) {
    grpc::ClientContext context;
    c.prepare(context, 3600);
    pb::WatchJobRequest request;
    request.set_job_id(id);
    request.set_previews(true);
    auto reader = c.stub().WatchJob(&context, request);
    pb::Job last;
    double renderingMs = -1;
    pb::JobEvent event;
    while (reader->Read(&event)) {
        double ms = secondsSince(submitted) * 1000;
        if (event.has_state()) {
            last = event.state();
            if (last.state() == pb::JOB_STATE_RENDERING && renderingMs < 0) renderingMs = ms;
            if (isTerminal(last.state())) break;
        } else if (event.has_progress()) {
            ++run.progressEvents;
        } else if (event.has_preview()) {
            notePreview(run, event.preview(), ms, renderingMs);
        }
    }
    run.times.wall = secondsSince(submitted);
    if (!isTerminal(last.state())) {
        grpc::Status status = reader->Finish();
        c.fail(status.ok() ? grpc::Status(grpc::StatusCode::UNKNOWN, "stream ended early") : status,
               "watch job " + id);
    }
    context.TryCancel();  // the server ends the stream anyway; do not wait for it
    reader->Finish();
    return last;
}

DaemonRun renderThroughDaemon(cli::Connection& c, const pb::JobSpec& spec) {
    pb::SubmitJobRequest request;
    *request.mutable_spec() = spec;
    DaemonRun run;
    auto submitted = Clock::now();
    std::string id = c.call(&pb::Partita::Stub::SubmitJob, request, "submit job").job_id();
    pb::Job job = watchToEnd(c, id, submitted, run);
    if (job.state() != pb::JOB_STATE_DONE)
        throw std::runtime_error("job " + id +
                                 " did not finish: " + pb::JobState_Name(job.state()) +
                                 (job.error().empty() ? "" : " (" + job.error() + ")"));
    run.times.algorithm = statOf(job, "seconds");
    run.times.passes = statOf(job, "render_seconds");
    run.times.passesCpu = statOf(job, "render_cpu_seconds");
    deleteJob(c, id);
    return run;
}

// ----- submit latency ------------------------------------------------------------------------

/// Times each SubmitJob call alone (the context is set up before the clock starts). The jobs
/// run meanwhile, as they would on a busy daemon.
std::vector<double> submitLatenciesMs(cli::Connection& c, const ServiceOptions& o,
                                      std::vector<std::string>& ids) {
    pb::SubmitJobRequest request;
    *request.mutable_spec() = tinySpec(o);
    std::vector<double> ms;
    for (int i = 0; i < o.jobs; ++i) {
        grpc::ClientContext context;
        c.prepare(context, 60);
        pb::SubmitJobResponse response;
        auto start = Clock::now();
        grpc::Status status = c.stub().SubmitJob(&context, request, &response);
        ms.push_back(secondsSince(start) * 1000);
        if (!status.ok()) c.fail(status, "submit job " + std::to_string(i + 1));
        ids.push_back(response.job_id());
    }
    return ms;
}

std::vector<pb::Job> listJobs(cli::Connection& c, const std::string& label) {
    pb::ListJobsRequest request;
    request.set_label(label);
    auto response = c.call(&pb::Partita::Stub::ListJobs, request, "list jobs");
    return {response.jobs().begin(), response.jobs().end()};
}

void cancelQuietly(cli::Connection& c, const std::string& id) {
    grpc::ClientContext context;
    c.prepare(context, 10);
    pb::CancelJobRequest request;
    request.set_job_id(id);
    pb::Job ignored;
    c.stub().CancelJob(&context, request, &ignored);
}

/// Waits until every job labelled `label` has ended (cancelling those still unfinished after
/// `patienceSeconds`), deletes them all and returns how many were DONE.
int finishAndDelete(cli::Connection& c, const std::string& label, double patienceSeconds) {
    auto start = Clock::now();
    bool cancelled = false;
    while (true) {
        std::vector<pb::Job> jobs = listJobs(c, label);
        bool allEnded = std::all_of(jobs.begin(), jobs.end(),
                                    [](const pb::Job& j) { return isTerminal(j.state()); });
        if (allEnded) {
            for (const auto& j : jobs) deleteJob(c, j.id());
            return int(std::count_if(jobs.begin(), jobs.end(), [](const pb::Job& j) {
                return j.state() == pb::JOB_STATE_DONE;
            }));
        }
        if (!cancelled && secondsSince(start) > patienceSeconds) {
            for (const auto& j : jobs)
                if (!isTerminal(j.state())) cancelQuietly(c, j.id());
            cancelled = true;
        }
        if (secondsSince(start) > patienceSeconds + 60)
            throw std::runtime_error("jobs labelled '" + label + "' did not end");
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

// ----- summaries -----------------------------------------------------------------------------

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n == 0 ? 0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double q) {
    size_t rank = size_t(std::ceil(q * double(sorted.size())));
    return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

nlohmann::json latencySummary(std::vector<double> ms) {
    std::sort(ms.begin(), ms.end());
    double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / double(ms.size());
    return {{"mean", mean},
            {"p50", percentile(ms, 0.50)},
            {"p95", percentile(ms, 0.95)},
            {"p99", percentile(ms, 0.99)},
            {"max", ms.back()}};
}

/// Samples/s of each run by one of its times: best (the least disturbed run) and median.
struct Rates {
    double best = 0, median = 0;
};

Rates ratesOf(const std::vector<RunTimes>& runs, double samples, double RunTimes::*time) {
    std::vector<double> r;
    for (const auto& run : runs) r.push_back(samples / (run.*time));
    return {*std::max_element(r.begin(), r.end()), eval::median(r)};
}

// ----- the measurements ----------------------------------------------------------------------

struct ThroughputResult {
    std::vector<RunTimes> inProcess;
    std::vector<DaemonRun> daemon;
};

/// In-process and daemon runs alternate, so that load from other processes hits both alike.
ThroughputResult measureThroughput(const ServiceOptions& o, int threads, cli::Connection& c) {
    ThreadPool pool(threads);
    pb::JobSpec spec = renderSpec(o, cli::loadSceneSource(cli::classifyScene(o.scene)));
    ThroughputResult r;
    for (int i = 0; i < o.repeats; ++i) {
        r.inProcess.push_back(renderInProcess(o, pool));
        r.daemon.push_back(renderThroughDaemon(c, spec));
        std::fprintf(stderr, "  run %d/%d: in-process %.2f s, daemon %.2f s (render)\n", i + 1,
                     o.repeats, r.inProcess.back().algorithm, r.daemon.back().times.algorithm);
    }
    return r;
}

void printRateRows(const char* name, const Rates& in, const Rates& daemon, const char* note) {
    std::printf("  %-34s best   %9.3f %9.3f %8.3f%s\n", name, in.best / 1e6, daemon.best / 1e6,
                daemon.best / in.best, note);
    std::printf("  %-34s median %9.3f %9.3f %8.3f\n", "", in.median / 1e6, daemon.median / 1e6,
                daemon.median / in.median);
}

/// Process CPU / wall during the passes: below the thread count means threads waited for a core.
nlohmann::json reportCoresBusy(const std::vector<RunTimes>& inProcess,
                               const std::vector<RunTimes>& daemon) {
    std::vector<double> in, d;
    for (const auto& t : inProcess) in.push_back(t.passesCpu / t.passes);
    for (const auto& t : daemon) d.push_back(t.passesCpu / t.passes);
    std::printf(
        "  cores busy during the passes (process CPU s / wall s, median): in-process %.2f, "
        "daemon %.2f\n",
        median(in), median(d));
    return {{"in_process_cores_busy", median(in)}, {"daemon_cores_busy", median(d)}};
}

nlohmann::json reportThroughput(const ServiceOptions& o, const ThroughputResult& r) {
    double samples = double(o.width) * o.height * o.spp;
    std::vector<RunTimes> daemon;
    for (const auto& d : r.daemon) daemon.push_back(d.times);
    Rates inRender = ratesOf(r.inProcess, samples, &RunTimes::algorithm);
    Rates dRender = ratesOf(daemon, samples, &RunTimes::algorithm);
    Rates inPasses = ratesOf(r.inProcess, samples, &RunTimes::passes);
    Rates dPasses = ratesOf(daemon, samples, &RunTimes::passes);
    Rates inWall = ratesOf(r.inProcess, samples, &RunTimes::wall);
    Rates dWall = ratesOf(daemon, samples, &RunTimes::wall);
    std::printf("  %-34s        %9s %9s %8s\n", "M samples/s", "in-proc", "daemon", "ratio");
    printRateRows("render (job stat \"seconds\")", inRender, dRender, "  (target >= 0.95)");
    printRateRows("sampling passes (\"render_seconds\")", inPasses, dPasses, "");
    printRateRows("end to end (wall clock)", inWall, dWall, "");
    nlohmann::json out;
    out["in_process_samples_per_s"] = inRender.best;
    out["daemon_samples_per_s"] = dRender.best;
    out["ratio"] = dRender.best / inRender.best;
    out["ratio_basis"] =
        "best of the repeats; time = the render statistic 'seconds' (first pass to final "
        "image, previews included), from the job's own statistics for the daemon";
    out["ratio_median"] = dRender.median / inRender.median;
    out["ratio_passes"] = dPasses.best / inPasses.best;
    out["ratio_end_to_end"] = dWall.best / inWall.best;
    out["in_process_best_wall_s"] = samples / inWall.best;
    out["daemon_best_submit_to_done_s"] = samples / dWall.best;
    out.update(reportCoresBusy(r.inProcess, daemon));
    return out;
}

nlohmann::json reportPreviews(const ServiceOptions& o, const ThroughputResult& r) {
    std::vector<double> first, afterRendering, previews, progress, kb;
    for (const auto& d : r.daemon) {
        first.push_back(d.firstPreviewMs);
        afterRendering.push_back(d.firstPreviewAfterRenderingMs);
        previews.push_back(d.previews);
        progress.push_back(d.progressEvents);
        kb.push_back(d.previewBytes / 1024);
    }
    // A frame well inside the first interval can only be an initial one; the pt integrator
    // publishes a preview after the first pass that ends at least one interval in.
    double after = median(afterRendering);
    bool periodic = after >= 0.5 * o.previewInterval * 1000;
    bool isFinal = r.daemon.front().firstPreviewFinal;
    std::string source = isFinal    ? "the final frame (the job ended within one interval)"
                         : periodic ? "the periodic interval (no initial frame)"
                                    : "an initial frame";
    std::printf(
        "  per daemon job (median): %.0f preview frames (%.0f KiB of PNG), %.0f progress "
        "events\n",
        median(previews), median(kb), median(progress));
    std::printf(
        "first preview (interval %.3g s): %.0f ms after SubmitJob, %.0f ms after the "
        "RENDERING event (median of %zu; best %.0f ms); it comes from %s\n",
        o.previewInterval, median(first), after, first.size(),
        *std::min_element(first.begin(), first.end()), source.c_str());
    return {{"first_preview_ms", median(first)}, {"first_preview_after_rendering_ms", after},
            {"first_preview_source", source},    {"preview_frames_per_job", median(previews)},
            {"preview_kib_per_job", median(kb)}, {"progress_events_per_job", median(progress)}};
}

nlohmann::json measureSubmitLatency(const ServiceOptions& o, cli::Connection& c) {
    std::vector<std::string> ids;
    std::vector<double> ms = submitLatenciesMs(c, o, ids);
    int done = finishAndDelete(c, kTinyLabel, 120);
    nlohmann::json s = latencySummary(ms);
    std::printf(
        "submit latency, %d jobs (16x16, 1 spp, scene '%s' by name): mean %.2f ms, p50 "
        "%.2f, p95 %.2f, p99 %.2f, max %.2f; %d done, all deleted\n",
        o.jobs, o.smallScene.c_str(), s["mean"].get<double>(), s["p50"].get<double>(),
        s["p95"].get<double>(), s["p99"].get<double>(), s["max"].get<double>(), done);
    return {{"submit_latency_ms", s}, {"jobs", o.jobs}, {"jobs_done", done}};
}

/// The daemon must take --jobs queued jobs (PrivateDaemon starts it with the default limits).
pb::ServerInfo checkServer(cli::Connection& c, const ServiceOptions& o) {
    auto info = c.call(&pb::Partita::Stub::GetServerInfo, pb::ServerInfoRequest(), "server info");
    if (o.jobs > info.limits().max_queued_jobs())
        throw std::runtime_error("--jobs " + std::to_string(o.jobs) + " exceeds the daemon's " +
                                 "queue limit of " +
                                 std::to_string(info.limits().max_queued_jobs()));
    return info;
}

}  // namespace

nlohmann::json runServiceBench(const ServiceOptions& o) {
    if (o.repeats < 1 || o.jobs < 1 || o.spp < 1)
        throw std::invalid_argument("--repeats, --jobs and --spp must be >= 1");
    int threads =
        o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    cli::PrivateDaemon daemon(cli::PrivateDaemon::Options{threads, 30});
    cli::Connection c(daemon.address(), cli::ServerOptions{});
    pb::ServerInfo info = checkServer(c, o);

    std::printf("service: %s (%dx%d, %d spp, seed %llu, pt, %d threads), %d interleaved runs\n",
                o.scene.c_str(), o.width, o.height, o.spp, (unsigned long long)o.seed, threads,
                o.repeats);
    std::printf(
        "  in-process: runRender, no previews; daemon: partitad %s (%d threads), previews "
        "every %.3g s, one WatchJob stream taking PNG previews\n",
        daemon.address().c_str(), info.threads(), o.previewInterval);
    ThroughputResult tp = measureThroughput(o, threads, c);
    nlohmann::json out = {{"scene", o.scene},
                          {"width", o.width},
                          {"height", o.height},
                          {"spp", o.spp},
                          {"threads", threads},
                          {"repeats", o.repeats},
                          {"preview_interval_s", o.previewInterval}};
    out.update(reportThroughput(o, tp));
    out.update(reportPreviews(o, tp));
    out.update(measureSubmitLatency(o, c));
    finishAndDelete(c, kRenderLabel, 0);  // nothing should be left; make sure
    return out;
}

}  // namespace partita::eval
