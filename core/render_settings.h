// Everything a render job can set, with the defaults of DESIGN.md. Shared by the offline front
// end, the service and the evaluation harness.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "params/parameter_values.h"
#include "params/settings_table.h"

namespace partita {

enum class BudgetKind { SamplesPerPixel, MutationsPerPixel, Seconds };

/// "spp", "mpp", "seconds": the budget's unit as the CLI's flags, metadata and keys name it.
const char* budgetKindName(BudgetKind kind);

/// The environment a job lights its scene with (glTF has none): an equirectangular EXR/HDR
/// file, or one colour, turned about +Y (environment_map.h). Neither: no environment.
struct EnvironmentSettings {
    std::string file;
    bool hasColor = false;
    std::array<float, 3> color{0, 0, 0};
    float rotationDegrees = 0;
    bool enabled() const { return !file.empty() || hasColor; }
};

/// What every algorithm reads (the shared parameters, declared once in sharedParameters()),
/// the budget, and the algorithm's own parameters by name.
struct RenderSettings {
    int width = 320, height = 240;
    std::string cameraName;  // empty = the scene's first camera (or a default framing camera)

    BudgetKind budgetKind = BudgetKind::SamplesPerPixel;
    double budget = 16;  // samples or mutations per pixel, or seconds

    uint64_t seed = 1;
    int maxDepth = 16;  // maximum number of scattering vertices on a path

    EnvironmentSettings environment;

    /// Path types with a layer of their own, chosen before the render (type_layer_rule.h); the
    /// rest sum into "other". Parameter "layers".
    int maxTypeLayers = 32;
    /// Keep a layer for every type that occurs, whatever maxTypeLayers: the film then grows
    /// with the scene's types (tests and tools comparing estimators type by type on tiny
    /// images; not a job parameter).
    bool everyTypeLayer = false;
    double previewIntervalSeconds = 1.0;

    /// The algorithm's own parameters (those its registry entry declares: k, y, radius, ...) as
    /// the job gives them; the algorithm's settings resolve from them, with its defaults for the
    /// rest (params/job_parameters.h).
    ParameterValues parameters;
};

/// The shared parameters, bound to RenderSettings' fields: width, height, camera, seed,
/// max_depth, layers, environment, environment_color, environment_rotation, preview_interval.
/// The budget is not among them: it travels as a kind and an amount.
const SettingsTable<RenderSettings>& sharedParameters();

/// Limits a front end checks before rendering; a violation is a clear error, never a crash.
struct RenderLimits {
    int maxWidth = 8192, maxHeight = 8192;
    double maxSamplesPerPixel = 1 << 20;
    double maxSeconds = 7 * 24 * 3600.0;
    int maxDepth = 1024;
    uint64_t maxBootstrapSamples = uint64_t(1) << 30;
};

/// Checks the shared parameters against their declarations, the budget, the limits and the
/// rules that join two settings (not both an environment file and a colour): "" when valid,
/// else one line saying what is wrong. The algorithm's own parameters are checked by
/// validateJob (params/job_parameters.h).
std::string validateSettings(const RenderSettings& settings, const RenderLimits& limits = {});

}  // namespace partita
