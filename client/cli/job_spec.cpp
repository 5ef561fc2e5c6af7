#include "cli/job_spec.h"

#include <climits>
#include <limits>

#include "cli/errors.h"
#include "params/job_parameters.h"
#include "render_settings.h"

namespace partita::cli {

void addJobOptions(CLI::App& app, JobFlags& flags, const std::string& helpAlgorithm) {
    addRenderOptions(app, flags.render, helpAlgorithm);
    app.add_option("--label", flags.label, "free text stored with the job (shown by 'jobs')");
    app.add_option("--priority", flags.priority, "higher runs first")->capture_default_str();
}

void setParameter(partita::v1::JobSpec& spec, const std::string& name, const std::string& text) {
    (*spec.mutable_parameters())[canonicalName(name)].set_text_value(text);
}

partita::v1::JobSpec makeJobSpec(const CLI::App&, const JobFlags& flags) {
    const RenderOptions& o = flags.render;
    partita::v1::JobSpec spec;
    if (o.algorithm.empty()) throw CliError("--algorithm must not be empty");
    spec.set_algorithm(o.algorithm);
    // --environment FILE travels with the scene: addEnvironmentImage, once the scene is known.
    for (const auto& [name, value] : o.given)
        if (name != "environment") setParameter(spec, name, std::get<std::string>(value));
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
    spec.set_priority(flags.priority);
    spec.set_label(flags.label);
    if (o.threads < 0 || o.threads > 4096) throw CliError("--threads must be in 0..4096");
    if (!o.settings.environment.file.empty() && o.settings.environment.hasColor)
        throw CliError("give --environment or --environment-color, not both");
    if (std::string err = validateJobSpec(spec); !err.empty()) throw CliError(err);
    return spec;
}

RenderSettings settingsOfSpec(const partita::v1::JobSpec& spec, std::string& error) {
    RenderSettings s;
    ParameterValues given;
    for (const auto& [name, value] : spec.parameters())
        given.set(name, value.has_text_value() ? value.text_value() : std::string());
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(spec.algorithm());
    if (!entry) {  // the server's own algorithm: only what is shared is known here
        AlgorithmRegistry::Entry sharedOnly;
        ParameterValues shared;
        for (const auto& [name, value] : given)
            if (findParameter(sharedParameters().specs(), canonicalName(name)))
                shared.setValue(name, value);
        error = applyJobParameters(sharedOnly, shared, s);
        return s;
    }
    error = applyJobParameters(*entry, given, s);
    if (spec.has_budget()) {
        s.budget = spec.budget().amount();
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
                if (error.empty()) error = "unknown budget kind";
        }
    }
    return s;
}

std::string validateJobSpec(const partita::v1::JobSpec& spec) {
    std::string error;
    RenderSettings s = settingsOfSpec(spec, error);
    if (!error.empty()) return error;
    const auto* entry = AlgorithmRegistry::instance().find(spec.algorithm());
    if (!entry) return "";  // the server checks its own algorithm's parameters
    // Only what is malformed here: the size, budget and depth limits are the server's own, read
    // from GetServerInfo (Session::checkLimits), not the core's defaults.
    RenderLimits unlimited;
    unlimited.maxWidth = unlimited.maxHeight = unlimited.maxDepth = INT_MAX;
    unlimited.maxSamplesPerPixel = unlimited.maxSeconds = std::numeric_limits<double>::max();
    unlimited.maxBootstrapSamples = std::numeric_limits<uint64_t>::max();
    return validateJob(*entry, s, unlimited);
}

}  // namespace partita::cli
