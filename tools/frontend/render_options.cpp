#include "frontend/render_options.h"

#include <set>

#include "algorithm.h"
#include "params/job_parameters.h"

namespace partita {

namespace {

std::string registeredNames() {
    registerBuiltinAlgorithms();
    std::string names;
    for (const auto& n : AlgorithmRegistry::instance().names())
        names += (names.empty() ? "" : " | ") + n;
    return names;
}

/// "R: radius of the candidates' disk (paper Eq. 18) [default 20; (0, 4096] pixels]".
std::string flagHelp(const ParameterSpec& spec, const std::string& takenBy) {
    std::string help = spec.help + " [";
    std::string def = formatParameter(spec, spec.defaultValue);
    if (!def.empty()) help += "default " + def + "; ";
    help += describeRange(spec);
    if (!spec.unit.empty()) help += " " + spec.unit;
    help += "]";
    if (!takenBy.empty()) help += " (" + takenBy + ")";
    return help;
}

/// Applies a shared parameter's text to `settings` at once, with the core's rule for it.
/// (Nothing for a name that is not a shared parameter.)
void applyShared(const std::string& name, const std::string& text, RenderOptions& o) {
    const auto* e = sharedParameters().find(name);
    if (!e) return;
    std::string error;
    std::optional<ParameterValue> v = acceptParameter(e->spec, text, error);
    if (!v) throw CLI::ValidationError("--" + flagName(name), error);
    e->set(o.settings, *v);
}

/// What --help shows for a value of `spec`: INT, REAL, auto|pt|bdpt, R,G,B, ...
std::string valueName(const ParameterSpec& spec) {
    switch (spec.type) {
        case ParameterType::Bool:
            return "true|false";
        case ParameterType::Int:
            return "INT";
        case ParameterType::UInt:
            return "UINT";
        case ParameterType::Real:
            return "REAL";
        case ParameterType::Text:
            return "TEXT";
        case ParameterType::Choice: {
            std::string out;
            for (const auto& c : spec.choices) out += (out.empty() ? "" : "|") + c;
            return out;
        }
        case ParameterType::Rgb:
            return "R,G,B";
    }
    return "VALUE";
}

void addParameterFlag(CLI::App& app, RenderOptions& o, const ParameterSpec& spec, bool shared,
                      const std::string& takenBy, const std::string& group) {
    std::string name = spec.name;
    auto* option = app.add_option_function<std::string>(
        "--" + flagName(name),
        [&o, name, shared](const std::string& text) {
            o.given.set(name, text);
            if (shared) applyShared(name, text, o);
        },
        flagHelp(spec, takenBy));
    option->group(group)->type_name(valueName(spec));
}

/// "--param NAME=VALUE": any parameter by name, checked when the options are finalised (or by
/// the server, for an algorithm this build does not have).
void addGenericParameter(CLI::App& app, RenderOptions& o) {
    app.add_option_function<std::vector<std::string>>(
           "--param",
           [&o](const std::vector<std::string>& items) {
               for (const auto& item : items) {
                   size_t eq = item.find('=');
                   if (eq == std::string::npos || eq == 0)
                       throw CLI::ValidationError("--param",
                                                  "expected NAME=VALUE, got '" + item + "'");
                   std::string name = canonicalName(item.substr(0, eq));
                   std::string text = item.substr(eq + 1);
                   o.given.set(name, text);
                   applyShared(name, text, o);
               }
           },
           "any declared parameter by name, e.g. --param radius=10 (repeatable; see --help with "
           "--algorithm for an algorithm's parameters)")
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

}  // namespace

std::string algorithmInArguments(int argc, const char* const* argv) {
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg == "--algorithm" && i + 1 < argc) return argv[i + 1];
        if (arg.rfind("--algorithm=", 0) == 0) return arg.substr(12);
    }
    return "";
}

void addRenderOptions(CLI::App& app, RenderOptions& o, const std::string& helpAlgorithm) {
    registerBuiltinAlgorithms();
    const auto& registry = AlgorithmRegistry::instance();
    app.add_option("--algorithm", o.algorithm,
                   registeredNames() + " (those of this build; a server may offer others)")
        ->capture_default_str();
    auto* spp = app.add_option("--spp", o.spp, "budget: samples per pixel");
    auto* mpp = app.add_option("--mpp", o.mpp, "budget: mutations per pixel");
    auto* sec = app.add_option("--seconds", o.seconds, "budget: wall-clock seconds");
    spp->excludes(mpp)->excludes(sec);
    mpp->excludes(sec);
    for (const auto& spec : sharedParameters().specs())
        addParameterFlag(app, o, spec, true, "", "Parameters of every algorithm");

    // Each algorithm parameter once, however many algorithms declare it.
    const AlgorithmRegistry::Entry* shown = registry.find(helpAlgorithm);
    std::set<std::string> added;
    for (const auto& algorithm : registry.names()) {
        for (const auto& spec : registry.find(algorithm)->parameters) {
            if (!added.insert(spec.name).second) continue;
            std::string takenBy;
            for (const auto& other : registry.names())
                if (findParameter(registry.find(other)->parameters, spec.name))
                    takenBy += (takenBy.empty() ? "" : ", ") + other;
            const ParameterSpec* own =
                shown ? findParameter(shown->parameters, spec.name) : nullptr;
            // An algorithm named on the command line: --help shows its parameters only, with
            // its own words for them.
            std::string group = shown ? (own ? "Parameters of " + shown->name : "")
                                      : "Parameters of the algorithms";
            addParameterFlag(app, o, own ? *own : spec, false, shown ? "" : takenBy, group);
        }
    }
    addGenericParameter(app, o);
    app.add_option("--threads", o.threads, "worker threads (0 = all)")->capture_default_str();
}

std::string finalizeRenderOptions(RenderOptions& o) {
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(o.algorithm);
    if (!entry) {
        std::string known;
        for (const auto& n : AlgorithmRegistry::instance().names())
            known += (known.empty() ? "" : ", ") + n;
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
    if (std::string err = applyJobParameters(*entry, o.given, s); !err.empty()) return err;
    return validateJob(*entry, s);
}

}  // namespace partita
