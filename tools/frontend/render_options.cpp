#include "frontend/render_options.h"

#include "algorithm.h"

namespace partita {

namespace {

/// "pt | bdpt": the algorithms this build registers (not the paper's list of planned ones).
std::string builtAlgorithms() {
    registerBuiltinAlgorithms();
    std::string names;
    for (const auto& n : AlgorithmRegistry::instance().names())
        names += (names.empty() ? "" : " | ") + n;
    return names;
}

}  // namespace

void addRenderOptions(CLI::App& app, RenderOptions& o) {
    RenderSettings& s = o.settings;
    app.add_option("--algorithm", o.algorithm,
                   builtAlgorithms() + " (those of this build; a server may offer others)")
        ->capture_default_str();
    auto* spp = app.add_option("--spp", o.spp, "budget: samples per pixel");
    auto* mpp = app.add_option("--mpp", o.mpp, "budget: mutations per pixel");
    auto* sec = app.add_option("--seconds", o.seconds, "budget: wall-clock seconds");
    spp->excludes(mpp)->excludes(sec);
    mpp->excludes(sec);
    app.add_option("--width", s.width, "image width in pixels")->capture_default_str();
    app.add_option("--height", s.height, "image height in pixels")->capture_default_str();
    app.add_option("--camera", s.cameraName, "camera name (default: the scene's first camera)");
    app.add_option("--seed", s.seed, "random seed")->capture_default_str();
    app.add_option("--max-depth", s.maxDepth, "maximum scattering vertices per path")
        ->capture_default_str();
    app.add_option("--k", s.partitions, "K: number of partitions (paper Sec. 4)")
        ->capture_default_str();
    app.add_option("--y", s.guideCandidates, "|Y'|: guide candidates per step (paper Sec. 5)")
        ->capture_default_str();
    app.add_option("--radius", s.guideRadius, "R: guide radius in pixels")->capture_default_str();
    app.add_option("--epsilon", s.guideEpsilon, "epsilon of Eq. 17")->capture_default_str();
    app.add_option("--bootstrap", s.bootstrapSamples,
                   "start-up samples of the MCMC methods (mlt: BDPT bootstrap; 0: 100000)")
        ->capture_default_str();
    app.add_option("--prepass", s.prepass,
                   "pre-pass of the partitioned methods: auto | pt | bdpt (auto: bdpt with delta "
                   "lights)")
        ->capture_default_str();
    app.add_option("--layers", s.maxTypeLayers, "path-type layers kept in the EXR before 'other'")
        ->capture_default_str();
    app.add_option("--environment", s.environment.file,
                   "equirectangular EXR/HDR lighting the scene from afar (+Y up, centre at -Z)");
    app.add_option_function<std::vector<float>>(
           "--environment-color",
           [&s](const std::vector<float>& c) {
               s.environment.hasColor = true;
               s.environment.color = {c[0], c[1], c[2]};
           },
           "uniform environment radiance R,G,B")
        ->delimiter(',')
        ->expected(3);
    app.add_option("--environment-rotation", s.environment.rotationDegrees,
                   "turn the environment about +Y, degrees")
        ->capture_default_str();
    app.add_option("--threads", o.threads, "worker threads (0 = all)")->capture_default_str();
}

}  // namespace partita
