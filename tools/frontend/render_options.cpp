#include "frontend/render_options.h"

#include "algorithm.h"

namespace partita {

void addRenderOptions(CLI::App& app, RenderOptions& o) {
    RenderSettings& s = o.settings;
    app.add_option("--algorithm", o.algorithm, "pt | bdpt | mlt | partitioned | guided (those built in)");
    auto* spp = app.add_option("--spp", o.spp, "budget: samples per pixel");
    auto* mpp = app.add_option("--mpp", o.mpp, "budget: mutations per pixel");
    auto* sec = app.add_option("--seconds", o.seconds, "budget: wall-clock seconds");
    spp->excludes(mpp)->excludes(sec);
    mpp->excludes(sec);
    app.add_option("--width", s.width, "image width in pixels")->capture_default_str();
    app.add_option("--height", s.height, "image height in pixels")->capture_default_str();
    app.add_option("--camera", s.cameraName, "camera name (default: the scene's first camera)");
    app.add_option("--seed", s.seed, "random seed")->capture_default_str();
    app.add_option("--max-depth", s.maxDepth, "maximum scattering vertices per path")->capture_default_str();
    app.add_option("--k", s.partitions, "K: number of partitions (paper Sec. 4)")->capture_default_str();
    app.add_option("--y", s.guideCandidates, "|Y'|: guide candidates per step (paper Sec. 5)")->capture_default_str();
    app.add_option("--radius", s.guideRadius, "R: guide radius in pixels")->capture_default_str();
    app.add_option("--epsilon", s.guideEpsilon, "epsilon of Eq. 17")->capture_default_str();
    app.add_option("--layers", s.maxTypeLayers, "path-type layers kept in the EXR before 'other'")
        ->capture_default_str();
    app.add_option("--threads", o.threads, "worker threads (0 = all)")->capture_default_str();
}

std::string finalizeRenderOptions(RenderOptions& o) {
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(o.algorithm);
    if (!entry) {
        std::string known;
        for (const auto& n : AlgorithmRegistry::instance().names()) known += (known.empty() ? "" : ", ") + n;
        return "unknown algorithm '" + o.algorithm + "' (available: " + known + ")";
    }
    RenderSettings& s = o.settings;
    if (o.spp) {
        s.budgetKind = BudgetKind::SamplesPerPixel;
        s.budget = *o.spp;
    } else if (o.mpp) {
        s.budgetKind = BudgetKind::MutationsPerPixel;
        s.budget = *o.mpp;
    } else if (o.seconds) {
        s.budgetKind = BudgetKind::Seconds;
        s.budget = *o.seconds;
    } else {
        s.budgetKind = entry->nativeBudget;
        s.budget = 16;
    }
    if (o.threads < 0 || o.threads > 4096) return "threads must be in 0..4096";
    return validateSettings(s);
}

}  // namespace partita
