#include "cli/sweep_axis.h"

#include <cmath>
#include <set>

#include "algorithm.h"
#include "cli/errors.h"
#include "cli/job_spec.h"
#include "params/job_parameters.h"

namespace partita::cli {

namespace {

bool isBudget(const std::string& name) {
    return name == "spp" || name == "mpp" || name == "seconds";
}

/// The declaration of `name` for `algorithm` in this build (nullopt: an algorithm or a
/// parameter only the server knows).
std::optional<ParameterSpec> declaration(const std::string& name, const std::string& algorithm) {
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(algorithm);
    auto specs = entry ? jobParameterSpecs(*entry) : sharedParameters().specs();
    const ParameterSpec* spec = findParameter(specs, canonicalName(name));
    return spec ? std::optional<ParameterSpec>(*spec) : std::nullopt;
}

/// "" when `value` reads as a value of the axis, else why not.
std::string checkValue(const std::string& name, const std::string& value,
                       const std::string& algorithm) {
    if (isBudget(name)) {
        char* end = nullptr;
        double v = std::strtod(value.c_str(), &end);
        return end == value.c_str() + value.size() && std::isfinite(v) && !value.empty()
                   ? ""
                   : "'" + value + "' is not a number";
    }
    std::optional<ParameterSpec> spec = declaration(name, algorithm);
    if (!spec) return "";
    std::string error;
    acceptParameter(*spec, value, error);
    return error;
}

}  // namespace

SweepAxis parseSweepAxis(const std::string& text, const std::string& algorithm) {
    auto bad = [&](const std::string& why) -> SweepAxis {
        throw CliError("bad --sweep '" + text + "': " + why +
                       " (expected NAME=V1,V2,... with NAME spp, mpp, seconds or a parameter of "
                       "the algorithm: see --help with --algorithm)");
    };
    size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) return bad("no NAME=");
    SweepAxis axis;
    axis.name = flagName(text.substr(0, eq));
    std::string list = text.substr(eq + 1);
    std::set<std::string> seen;
    size_t start = 0;
    while (true) {
        size_t comma = list.find(',', start);
        std::string v =
            list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (v.empty()) return bad("empty value");
        if (std::string why = checkValue(axis.name, v, algorithm); !why.empty()) return bad(why);
        if (!seen.insert(v).second) return bad("value '" + v + "' repeats");
        axis.values.push_back(v);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return axis;
}

void applySweepValue(partita::v1::JobSpec& spec, const std::string& name,
                     const std::string& value) {
    auto budget = [&](partita::v1::BudgetKind kind) {
        spec.mutable_budget()->set_kind(kind);
        spec.mutable_budget()->set_amount(std::strtod(value.c_str(), nullptr));
    };
    if (name == "spp")
        budget(partita::v1::BUDGET_KIND_SAMPLES_PER_PIXEL);
    else if (name == "mpp")
        budget(partita::v1::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    else if (name == "seconds")
        budget(partita::v1::BUDGET_KIND_SECONDS);
    else
        setParameter(spec, name, value);
}

}  // namespace partita::cli
