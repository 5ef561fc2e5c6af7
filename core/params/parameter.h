// A job parameter as it is declared once, next to the settings it fills (after Mitsuba's typed
// Properties and pbrt-v4's ParameterDictionary): its one name, type, default, range, unit and
// one-line help. The CLI's flags and --help, the service's validation and GetServerInfo, the
// job's metadata and EXR attributes, the reference-cache key and the shard plan all read these
// declarations (params/settings_table.h binds them to a struct; params/job_parameters.h gathers
// a job's), so a new setting is one declaration.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace partita {

enum class ParameterType { Bool, Int, UInt, Real, Text, Choice, Rgb };

using RgbValue = std::array<double, 3>;

/// A parameter's value. monostate: unset, for a parameter without a default (an environment
/// colour); a Choice holds its text.
using ParameterValue =
    std::variant<std::monostate, bool, int64_t, uint64_t, double, std::string, RgbValue>;

struct ParameterSpec {
    /// One name everywhere: the wire's parameter map, the metadata, `partita:NAME` in the EXR,
    /// the reference key, and the CLI flag `--NAME` (written with '-' for '_').
    std::string name;
    std::string help;  // one line
    std::string unit;  // "pixels", "samples", ...; may be empty
    /// Inclusive bounds of a number (of each component of an RGB); minExclusive makes the
    /// lower one strict.
    std::optional<double> min, max;
    bool minExclusive = false;
    std::vector<std::string> choices;  // a Choice's values
    size_t maxLength = 1024;           // a Text's bytes
    /// A rule beyond the range (a file extension, say): "" or why the value is refused.
    std::function<std::string(const ParameterValue&)> check;

    // Filled by the binding (settings_table.h) from the field's type and default:
    ParameterType type = ParameterType::Real;
    ParameterValue defaultValue;
    bool singlePrecision = false;  // a float field: values are rounded to float and print shortest

    ParameterSpec() = default;
    ParameterSpec(std::string name, std::string help)
        : name(std::move(name)), help(std::move(help)) {}
    // A declaration reads as one expression:
    //   ParameterSpec("radius", "R: ...").withUnit("pixels").above(0).atMost(4096)
    ParameterSpec& withUnit(std::string u) { return unit = std::move(u), *this; }
    ParameterSpec& atLeast(double lo) { return min = lo, minExclusive = false, *this; }
    ParameterSpec& above(double lo) { return min = lo, minExclusive = true, *this; }
    ParameterSpec& atMost(double hi) { return max = hi, *this; }
    ParameterSpec& within(double lo, double hi) { return atLeast(lo).atMost(hi); }
    ParameterSpec& withChoices(std::vector<std::string> c) { return choices = std::move(c), *this; }
    ParameterSpec& withMaxLength(size_t n) { return maxLength = n, *this; }
    ParameterSpec& withCheck(std::function<std::string(const ParameterValue&)> f) {
        return check = std::move(f), *this;
    }
    ParameterSpec& ofType(ParameterType t, bool single = false) {
        return type = t, singlePrecision = single, *this;
    }
};

const char* parameterTypeName(ParameterType type);

/// The CLI's spelling of a name: '_' written as '-' ("max_depth" -> "max-depth").
std::string flagName(std::string_view name);
/// The canonical spelling of a name written either way ("max-depth" -> "max_depth").
std::string canonicalName(std::string_view name);

/// The value as text that parseParameter reads back to the same value: "20", "0.01", "auto",
/// "1,0.5,0.25", "true"; "" for unset.
std::string formatParameter(const ParameterSpec& spec, const ParameterValue& value);

/// Reads `text` as a value of spec's type (not yet range-checked): the value, or nullopt with
/// `error` saying why, naming the parameter.
std::optional<ParameterValue> parseParameter(const ParameterSpec& spec, std::string_view text,
                                             std::string& error);

/// The value in spec's own type, where the conversion is exact (a whole Real for an Int, an Int
/// for a Real, text for anything): what a client sent as another type. nullopt with `error`
/// when it cannot be.
std::optional<ParameterValue> coerceParameter(const ParameterSpec& spec,
                                              const ParameterValue& value, std::string& error);

/// "" when `value` (in spec's type) keeps every rule of spec, else one line naming the
/// parameter and the rule: "radius = 0 is outside (0, 4096] pixels".
std::string checkParameter(const ParameterSpec& spec, const ParameterValue& value);

/// What a given value means for spec: converted to its type (coerceParameter) and checked
/// (checkParameter); unset (monostate) is the default. nullopt with `error` when refused. The
/// one reading of a given value that every front end and the daemon share.
std::optional<ParameterValue> acceptParameter(const ParameterSpec& spec,
                                              const ParameterValue& given, std::string& error);

/// The rule as text: "(0, 4096]", "auto | pt | bdpt", "any"; for --help and error messages.
std::string describeRange(const ParameterSpec& spec);

/// The declaration named `name` in `specs`, or null.
const ParameterSpec* findParameter(const std::vector<ParameterSpec>& specs, std::string_view name);

}  // namespace partita
