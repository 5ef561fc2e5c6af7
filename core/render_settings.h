// Everything a render job can set, with the defaults of DESIGN.md. Shared by the offline front
// end, the service and the evaluation harness.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace partita {

enum class BudgetKind { SamplesPerPixel, MutationsPerPixel, Seconds };

/// The environment a job lights its scene with (glTF has none): an equirectangular EXR/HDR
/// file, or one colour, turned about +Y (environment_map.h). Neither: no environment.
struct EnvironmentSettings {
    std::string file;
    bool hasColor = false;
    std::array<float, 3> color{0, 0, 0};
    float rotationDegrees = 0;
    bool enabled() const { return !file.empty() || hasColor; }
};

struct RenderSettings {
    int width = 320, height = 240;
    std::string cameraName;  // empty = the scene's first camera (or a default framing camera)

    BudgetKind budgetKind = BudgetKind::SamplesPerPixel;
    double budget = 16;  // samples or mutations per pixel, or seconds

    uint64_t seed = 1;
    int maxDepth = 16;  // maximum number of scattering vertices on a path

    // Method parameters (paper Section 4-5); ignored by algorithms that do not use them.
    int partitions = 10;         // K
    // |Y'|, R and epsilon: chosen with the |Y'| x R study and the epsilon sweep of bench/README.md,
    // "guided: the |Y'| x R study (issue #13 item 6)" (cornell-glass and bathroom, 32 mpp, RMSE
    // ratios paired by seed). |Y'| = 128, the paper's: 32 and 512 tie with it within about two
    // standard errors, 8 loses 1..47% and shows structured noise. R = 20: at 128x96 (12 seeds)
    // R = 5..40 tie within 1.5% and R = 2 loses 5..12%; at 256x192 (4 seeds) R = 5 loses 2..4%,
    // R = 20 ties with 10 on cornell-glass and beats it on bathroom (0.92x): the good range moves
    // up with the image, so much wider images may want a larger R. epsilon (relative to D_i's
    // mean, image_guide.h): 0.001..0.1 tie within 0.5% on cornell-glass (3% on bathroom, within
    // its noise); 0.01 is the middle of that flat range.
    int guideCandidates = 128;   // |Y'|
    float guideRadius = 20;      // R, pixels
    float guideEpsilon = 0.01f;  // epsilon of Eq. 17
    /// Samples of the MCMC methods' start-up (mlt's BDPT bootstrap, partitioned's pre-pass);
    /// 0: the algorithm's default.
    uint64_t bootstrapSamples = 0;
    /// The pre-pass estimator of the partitioned methods: "pt" (the paper's), "bdpt" or "auto"
    /// (bdpt when the scene has a delta light, else pt). Default bdpt, the estimator of mlt's
    /// start-up: at the same 100000 samples its b_i are less noisy than the path tracer's (the
    /// sum of b_i spreads 3-4% over seeds with pt), and partitioned's RMSE at 32 mpp went from
    /// 0.99-1.33x mlt's to 0.84-0.98x on every shipped scene (bench/README.md, "partitioned
    /// against mlt and pt").
    std::string prepass = "bdpt";

    EnvironmentSettings environment;

    int maxTypeLayers = 32;  // film layers kept before the rest merge into "other"
    double previewIntervalSeconds = 1.0;
};

/// Limits a front end checks before rendering; a violation is a clear error, never a crash.
struct RenderLimits {
    int maxWidth = 8192, maxHeight = 8192;
    double maxSamplesPerPixel = 1 << 20;
    double maxSeconds = 7 * 24 * 3600.0;
    int maxDepth = 1024;
    uint64_t maxBootstrapSamples = uint64_t(1) << 30;
};

/// Returns an empty string when the settings are valid, else one line saying what is wrong.
std::string validateSettings(const RenderSettings& settings, const RenderLimits& limits = {});

}  // namespace partita
