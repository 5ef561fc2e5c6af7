#include "params/job_parameters.h"

#include <stdexcept>

namespace partita {

namespace {

std::string nameList(const std::vector<ParameterSpec>& specs) {
    std::string out;
    for (const auto& s : specs) out += (out.empty() ? "" : ", ") + s.name;
    return out.empty() ? "none" : out;
}

/// acceptParameter as "" or the error line, the value in `out`.
std::string convert(const ParameterSpec& spec, const ParameterValue& given, ParameterValue& out) {
    std::string error;
    std::optional<ParameterValue> v = acceptParameter(spec, given, error);
    if (v) out = std::move(*v);
    return error;
}

std::string unknown(const AlgorithmRegistry::Entry& entry, const std::string& name) {
    std::string shown;
    for (char c : name.substr(0, 64)) shown += (c >= 0x20 && c < 0x7f) ? c : '?';
    return "unknown parameter '" + shown + "' for " + entry.name +
           " (its parameters: " + nameList(jobParameterSpecs(entry)) + ")";
}

}  // namespace

const AlgorithmRegistry::Entry& registeredAlgorithm(const std::string& name) {
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(name);
    if (entry) return *entry;
    std::string names;
    for (const auto& n : AlgorithmRegistry::instance().names())
        names += (names.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown algorithm '" + name + "' (there are: " + names + ")");
}

std::vector<ParameterSpec> jobParameterSpecs(const AlgorithmRegistry::Entry& entry) {
    std::vector<ParameterSpec> out = sharedParameters().specs();
    out.insert(out.end(), entry.parameters.begin(), entry.parameters.end());
    return out;
}

std::string applyJobParameters(const AlgorithmRegistry::Entry& entry, const ParameterValues& given,
                               RenderSettings& settings) {
    for (const auto& [written, value] : given) {
        std::string name = canonicalName(written);
        ParameterValue v;
        if (const auto* e = sharedParameters().find(name)) {
            if (std::string why = convert(e->spec, value, v); !why.empty()) return why;
            e->set(settings, v);
        } else if (const ParameterSpec* spec = findParameter(entry.parameters, name)) {
            if (std::string why = convert(*spec, value, v); !why.empty()) return why;
            settings.parameters.setValue(name, std::move(v));
        } else {
            return unknown(entry, written);
        }
    }
    return "";
}

std::vector<JobParameter> jobParameters(const AlgorithmRegistry::Entry& entry,
                                        const RenderSettings& settings) {
    std::vector<JobParameter> out;
    for (const auto& e : sharedParameters().entries()) out.push_back({&e.spec, e.get(settings)});
    for (const auto& spec : entry.parameters) {
        ParameterValue v = spec.defaultValue;
        if (const ParameterValue* given = settings.parameters.find(spec.name))
            if (std::string why = convert(spec, *given, v); !why.empty())
                throw std::invalid_argument(why);
        out.push_back({&spec, std::move(v)});
    }
    return out;
}

void fillAlgorithmDefaults(const AlgorithmRegistry::Entry& entry, RenderSettings& settings) {
    for (const auto& spec : entry.parameters)
        if (!settings.parameters.has(spec.name))
            settings.parameters.setValue(spec.name, spec.defaultValue);
}

std::string validateJob(const AlgorithmRegistry::Entry& entry, const RenderSettings& settings,
                        const RenderLimits& limits) {
    if (std::string why = validateSettings(settings, limits); !why.empty()) return why;
    for (const auto& [name, value] : settings.parameters) {
        const ParameterSpec* spec = findParameter(entry.parameters, name);
        if (!spec) return unknown(entry, name);
        ParameterValue v;
        if (std::string why = convert(*spec, value, v); !why.empty()) return why;
        if (const auto* samples = std::get_if<uint64_t>(&v);
            samples && name == "bootstrap" && *samples > limits.maxBootstrapSamples)
            return "bootstrap = " + std::to_string(*samples) + " samples exceeds the limit of " +
                   std::to_string(limits.maxBootstrapSamples);
    }
    return "";
}

}  // namespace partita
