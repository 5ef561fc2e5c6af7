#include "parameter_wire.h"

#include "params/job_parameters.h"

namespace partita::server {

ParameterValue fromWire(const pb::ParameterValue& value) {
    switch (value.value_case()) {
        case pb::ParameterValue::kBoolValue:
            return value.bool_value();
        case pb::ParameterValue::kIntValue:
            return int64_t(value.int_value());
        case pb::ParameterValue::kUintValue:
            return uint64_t(value.uint_value());
        case pb::ParameterValue::kRealValue:
            return value.real_value();
        case pb::ParameterValue::kTextValue:
            return value.text_value();
        case pb::ParameterValue::kRgbValue:
            return RgbValue{value.rgb_value().r(), value.rgb_value().g(), value.rgb_value().b()};
        case pb::ParameterValue::VALUE_NOT_SET:
            break;
    }
    return std::monostate{};
}

void toWire(const ParameterValue& value, pb::ParameterValue& out) {
    out.Clear();
    std::visit(
        [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, bool>)
                out.set_bool_value(v);
            else if constexpr (std::is_same_v<T, int64_t>)
                out.set_int_value(v);
            else if constexpr (std::is_same_v<T, uint64_t>)
                out.set_uint_value(v);
            else if constexpr (std::is_same_v<T, double>)
                out.set_real_value(v);
            else if constexpr (std::is_same_v<T, std::string>)
                out.set_text_value(v);
            else if constexpr (std::is_same_v<T, RgbValue>) {
                out.mutable_rgb_value()->set_r(v[0]);
                out.mutable_rgb_value()->set_g(v[1]);
                out.mutable_rgb_value()->set_b(v[2]);
            }
        },
        value);
}

namespace {

/// The typed fields of JobSpec older clients set, each under its parameter's name; a field at
/// its "unset" value (an empty text, bootstrap_samples 0) gives nothing.
std::string typedFields(const pb::JobSpec& spec, ParameterValues& out) {
    if (spec.has_width()) out.set("width", spec.width());
    if (spec.has_height()) out.set("height", spec.height());
    if (!spec.camera().empty()) out.set("camera", spec.camera());
    if (spec.has_seed()) out.set("seed", spec.seed());
    if (spec.has_max_depth()) out.set("max_depth", spec.max_depth());
    if (spec.has_max_type_layers()) out.set("layers", spec.max_type_layers());
    if (spec.has_preview_interval_seconds())
        out.set("preview_interval", spec.preview_interval_seconds());
    if (!spec.environment_file().empty()) out.set("environment", spec.environment_file());
    if (spec.environment_color_size() != 0) {
        if (spec.environment_color_size() != 3)
            return "environment_color needs 3 values (R, G, B), got " +
                   std::to_string(spec.environment_color_size());
        out.set("environment_color", RgbValue{spec.environment_color(0), spec.environment_color(1),
                                              spec.environment_color(2)});
    }
    if (spec.has_environment_rotation_degrees())
        out.set("environment_rotation", spec.environment_rotation_degrees());
    if (spec.has_k()) out.set("k", spec.k());
    if (spec.has_y()) out.set("y", spec.y());
    if (spec.has_radius()) out.set("radius", spec.radius());
    if (spec.has_epsilon()) out.set("epsilon", spec.epsilon());
    if (!spec.prepass().empty()) out.set("prepass", spec.prepass());
    if (spec.has_bootstrap_samples() && spec.bootstrap_samples() > 0)
        out.set("bootstrap", spec.bootstrap_samples());
    return "";
}

/// Whether two given values are the same value of `spec` (both converted to its type).
bool sameValue(const ParameterSpec& spec, const ParameterValue& a, const ParameterValue& b) {
    std::string error;
    auto ca = coerceParameter(spec, a, error), cb = coerceParameter(spec, b, error);
    return ca && cb && *ca == *cb;
}

}  // namespace

std::string givenParameters(const AlgorithmRegistry::Entry& entry, const pb::JobSpec& spec,
                            ParameterValues& out) {
    out = {};
    if (std::string why = typedFields(spec, out); !why.empty()) return why;
    std::vector<ParameterSpec> specs = jobParameterSpecs(entry);
    for (const auto& [written, value] : spec.parameters()) {
        std::string name = canonicalName(written);
        ParameterValue v = fromWire(value);
        if (const ParameterValue* typed = out.find(name)) {
            const ParameterSpec* declared = findParameter(specs, name);
            if (declared && !sameValue(*declared, *typed, v))
                return "parameter " + name +
                       " is given twice with two values (its typed field and parameters)";
        }
        out.setValue(name, std::move(v));
    }
    return "";
}

void storeResolvedParameters(const AlgorithmRegistry::Entry& entry, const RenderSettings& settings,
                             pb::JobSpec& spec) {
    auto* map = spec.mutable_parameters();
    map->clear();
    for (const JobParameter& p : jobParameters(entry, settings))
        if (!std::holds_alternative<std::monostate>(p.value)) toWire(p.value, (*map)[p.spec->name]);
}

void describeAlgorithmParameters(const AlgorithmRegistry::Entry& entry, pb::AlgorithmInfo& info) {
    for (BudgetKind kind : entry.budgets()) info.add_parameters(budgetKindName(kind));
    size_t shared = sharedParameters().specs().size(), index = 0;
    for (const ParameterSpec& spec : jobParameterSpecs(entry)) {
        info.add_parameters(flagName(spec.name));
        pb::ParameterInfo* p = info.add_parameter_info();
        p->set_name(spec.name);
        p->set_type(parameterTypeName(spec.type));
        p->set_help(spec.help);
        p->set_unit(spec.unit);
        if (!std::holds_alternative<std::monostate>(spec.defaultValue))
            toWire(spec.defaultValue, *p->mutable_default_value());
        if (spec.min) p->set_min(*spec.min);
        if (spec.max) p->set_max(*spec.max);
        p->set_min_exclusive(spec.minExclusive);
        for (const auto& c : spec.choices) p->add_choices(c);
        p->set_shared(index++ < shared);
    }
}

}  // namespace partita::server
