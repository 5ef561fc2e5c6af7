#include "cli/job_format.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "frontend/progress_bar.h"

namespace partita::cli {

std::string stateName(partita::v1::JobState state) {
    using namespace partita::v1;
    switch (state) {
        case JOB_STATE_QUEUED:
            return "queued";
        case JOB_STATE_LOADING:
            return "loading";
        case JOB_STATE_PREPASS:
            return "prepass";
        case JOB_STATE_RENDERING:
            return "rendering";
        case JOB_STATE_DONE:
            return "done";
        case JOB_STATE_FAILED:
            return "failed";
        case JOB_STATE_CANCELLED:
            return "cancelled";
        default:
            return "unknown";
    }
}

bool isTerminal(partita::v1::JobState state) {
    return state == partita::v1::JOB_STATE_DONE || state == partita::v1::JOB_STATE_FAILED ||
           state == partita::v1::JOB_STATE_CANCELLED;
}

RenderProgress toRenderProgress(const partita::v1::Progress& p) {
    RenderProgress r;
    r.phase = p.phase();
    r.done = p.done();
    r.total = p.total();
    r.unit = p.unit();
    r.ratePerSecond = p.rate_per_second();
    r.etaSeconds = p.eta_seconds();
    r.elapsedSeconds = p.elapsed_seconds();
    for (const auto& part : p.partitions())
        r.partitions.push_back({part.type(), part.acceptance(), part.b(), part.p(), part.gamma(),
                                part.estimator(), part.move()});
    r.values.insert(p.values().begin(), p.values().end());
    return r;
}

std::string progressText(const partita::v1::Job& job) {
    if (job.state() == partita::v1::JOB_STATE_DONE) return "100%";
    // A job without progress yet may carry a note, e.g. why it was re-queued.
    if (!job.has_progress()) return job.note().empty() ? "-" : "- (" + job.note() + ")";
    const auto& p = job.progress();
    char buf[64];
    if (p.total() > 0) {
        std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * std::min(1.0, p.done() / p.total()));
        return buf;
    }
    if (p.done() > 0) return humanCount(p.done()) + p.unit();
    return "-";
}

double jobSeconds(const partita::v1::Job& job) {
    auto it = job.stats().find("seconds");
    if (it != job.stats().end() && std::isfinite(it->second)) return it->second;
    if (job.started_unix_ms() > 0 && job.finished_unix_ms() >= job.started_unix_ms())
        return double(job.finished_unix_ms() - job.started_unix_ms()) / 1000.0;
    return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace partita::cli
