#include "cli/job_spec.h"

#include <climits>
#include <limits>

#include "cli/errors.h"
#include "render_settings.h"

namespace partita::cli {

void addJobOptions(CLI::App& app, JobFlags& flags) {
    addRenderOptions(app, flags.render);
    app.add_option("--label", flags.label, "free text stored with the job (shown by 'jobs')");
    app.add_option("--priority", flags.priority, "higher runs first")->capture_default_str();
    app.add_option("--preview-interval", flags.previewInterval,
                   "seconds between preview frames (server default: 1)");
}

partita::v1::JobSpec makeJobSpec(const CLI::App& app, const JobFlags& flags) {
    const RenderOptions& o = flags.render;
    const RenderSettings& s = o.settings;
    auto given = [&](const char* name) { return app.count(name) > 0; };
    partita::v1::JobSpec spec;
    spec.set_algorithm(o.algorithm);
    if (given("--width")) spec.set_width(s.width);
    if (given("--height")) spec.set_height(s.height);
    if (given("--camera")) spec.set_camera(s.cameraName);
    if (given("--seed")) spec.set_seed(s.seed);
    if (given("--max-depth")) spec.set_max_depth(s.maxDepth);
    if (given("--k")) spec.set_k(s.partitions);
    if (given("--prepass")) spec.set_prepass(s.prepass);
    if (given("--bootstrap")) spec.set_bootstrap_samples(s.bootstrapSamples);
    if (given("--y")) spec.set_y(s.guideCandidates);
    if (given("--radius")) spec.set_radius(s.guideRadius);
    if (given("--epsilon")) spec.set_epsilon(s.guideEpsilon);
    if (given("--layers")) spec.set_max_type_layers(s.maxTypeLayers);
    // --environment FILE travels with the scene: addEnvironmentImage, once the scene is known.
    if (!s.environment.file.empty() && s.environment.hasColor)
        throw CliError("give --environment or --environment-color, not both");
    if (s.environment.hasColor)
        for (float c : s.environment.color) spec.add_environment_color(c);
    if (given("--environment-rotation"))
        spec.set_environment_rotation_degrees(s.environment.rotationDegrees);
    if (o.spp) {
        spec.mutable_budget()->set_kind(partita::v1::BUDGET_KIND_SAMPLES_PER_PIXEL);
        spec.mutable_budget()->set_amount(*o.spp);
    } else if (o.mpp) {
        spec.mutable_budget()->set_kind(partita::v1::BUDGET_KIND_MUTATIONS_PER_PIXEL);
        spec.mutable_budget()->set_amount(*o.mpp);
    } else if (o.seconds) {
        spec.mutable_budget()->set_kind(partita::v1::BUDGET_KIND_SECONDS);
        spec.mutable_budget()->set_amount(*o.seconds);
    }
    if (flags.previewInterval) spec.set_preview_interval_seconds(*flags.previewInterval);
    spec.set_priority(flags.priority);
    spec.set_label(flags.label);
    if (o.algorithm.empty()) throw CliError("--algorithm must not be empty");
    if (o.threads < 0 || o.threads > 4096) throw CliError("--threads must be in 0..4096");
    if (std::string err = validateJobSpec(spec); !err.empty()) throw CliError(err);
    return spec;
}

std::string validateJobSpec(const partita::v1::JobSpec& spec) {
    RenderSettings s;
    if (spec.has_width()) s.width = spec.width();
    if (spec.has_height()) s.height = spec.height();
    if (spec.has_seed()) s.seed = spec.seed();
    if (spec.has_max_depth()) s.maxDepth = spec.max_depth();
    if (spec.has_k()) s.partitions = spec.k();
    if (!spec.prepass().empty()) s.prepass = spec.prepass();
    if (spec.has_bootstrap_samples()) s.bootstrapSamples = spec.bootstrap_samples();
    if (spec.has_y()) s.guideCandidates = spec.y();
    if (spec.has_radius()) s.guideRadius = spec.radius();
    if (spec.has_epsilon()) s.guideEpsilon = spec.epsilon();
    if (spec.has_max_type_layers()) s.maxTypeLayers = spec.max_type_layers();
    if (spec.environment_color_size() == 3) {
        s.environment.hasColor = true;
        for (int k = 0; k < 3; ++k) s.environment.color[size_t(k)] = spec.environment_color(k);
    }
    if (spec.has_environment_rotation_degrees())
        s.environment.rotationDegrees = spec.environment_rotation_degrees();
    if (spec.has_preview_interval_seconds())
        s.previewIntervalSeconds = spec.preview_interval_seconds();
    if (spec.has_budget()) {
        switch (spec.budget().kind()) {
            case partita::v1::BUDGET_KIND_SAMPLES_PER_PIXEL:
                s.budgetKind = BudgetKind::SamplesPerPixel;
                break;
            case partita::v1::BUDGET_KIND_MUTATIONS_PER_PIXEL:
                s.budgetKind = BudgetKind::MutationsPerPixel;
                break;
            case partita::v1::BUDGET_KIND_SECONDS:
                s.budgetKind = BudgetKind::Seconds;
                break;
            default:
                return "unknown budget kind";
        }
        s.budget = spec.budget().amount();
    }
    // Only what is malformed here: the size, budget and depth limits are the server's own, read
    // from GetServerInfo (Session::checkLimits), not the core's defaults.
    RenderLimits unlimited;
    unlimited.maxWidth = unlimited.maxHeight = unlimited.maxDepth = INT_MAX;
    unlimited.maxSamplesPerPixel = unlimited.maxSeconds = std::numeric_limits<double>::max();
    return validateSettings(s, unlimited);
}

}  // namespace partita::cli
