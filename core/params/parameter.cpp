#include "params/parameter.h"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>

namespace partita {

namespace {

/// Untrusted text as it may appear in a message: printable ASCII, at most 64 bytes.
std::string printable(std::string_view text) {
    std::string out;
    for (char c : text.substr(0, 64)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
    if (text.size() > 64) out += "...";
    return out;
}

std::string number(double v, bool single) {
    return single ? fmt::format("{}", float(v)) : fmt::format("{}", v);
}

bool parseReal(std::string_view text, double& out) {
    if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return false;
    std::string s(text);
    char* end = nullptr;
    errno = 0;
    out = std::strtod(s.c_str(), &end);
    return errno == 0 && end == s.c_str() + s.size() && std::isfinite(out);
}

bool parseInt(std::string_view text, int64_t& out) {
    if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return false;
    std::string s(text);
    char* end = nullptr;
    errno = 0;
    long long v = std::strtoll(s.c_str(), &end, 10);
    out = v;
    return errno == 0 && end == s.c_str() + s.size();
}

bool parseUInt(std::string_view text, uint64_t& out) {
    if (text.empty() || text.front() == '-' || text.front() == '+' ||
        std::isspace(static_cast<unsigned char>(text.front())))
        return false;
    std::string s(text);
    char* end = nullptr;
    errno = 0;
    unsigned long long v = std::strtoull(s.c_str(), &end, 10);
    out = v;
    return errno == 0 && end == s.c_str() + s.size();
}

/// A Real as the field holds it: rounded to float for a float field.
std::optional<double> realOf(const ParameterSpec& spec, double v, std::string& error) {
    if (!std::isfinite(v)) {
        error = spec.name + " must be a finite number";
        return std::nullopt;
    }
    if (!spec.singlePrecision) return v;
    if (std::abs(v) > double(FLT_MAX)) {
        error = spec.name + " = " + number(v, false) + " is too large";
        return std::nullopt;
    }
    return double(float(v));
}

bool inRange(const ParameterSpec& spec, double v) {
    if (spec.min && (spec.minExclusive ? v <= *spec.min : v < *spec.min)) return false;
    if (spec.max && v > *spec.max) return false;
    return true;
}

/// "radius = 0 is outside (0, 4096] pixels"; a bound on one side: "width = 0 must be >= 1".
std::string outside(const ParameterSpec& spec, const std::string& shown) {
    if (spec.min && spec.max) {
        std::string unit = spec.unit.empty() ? "" : " " + spec.unit;
        return spec.name + " = " + shown + " is outside " + describeRange(spec) + unit;
    }
    return spec.name + " = " + shown + " must be " + describeRange(spec);
}

const char* typeError(ParameterType type) {
    switch (type) {
        case ParameterType::Bool:
            return "true or false";
        case ParameterType::Int:
            return "a whole number";
        case ParameterType::UInt:
            return "a whole number >= 0";
        case ParameterType::Real:
            return "a number";
        case ParameterType::Text:
            return "text";
        case ParameterType::Choice:
            return "one of its choices";
        case ParameterType::Rgb:
            return "three numbers R,G,B";
    }
    return "?";
}

}  // namespace

const char* parameterTypeName(ParameterType type) {
    switch (type) {
        case ParameterType::Bool:
            return "bool";
        case ParameterType::Int:
            return "int";
        case ParameterType::UInt:
            return "uint";
        case ParameterType::Real:
            return "real";
        case ParameterType::Text:
            return "text";
        case ParameterType::Choice:
            return "choice";
        case ParameterType::Rgb:
            return "rgb";
    }
    return "?";
}

std::string flagName(std::string_view name) {
    std::string out(name);
    std::replace(out.begin(), out.end(), '_', '-');
    return out;
}

std::string canonicalName(std::string_view name) {
    std::string out(name);
    std::replace(out.begin(), out.end(), '-', '_');
    return out;
}

std::string formatParameter(const ParameterSpec& spec, const ParameterValue& value) {
    bool single = spec.singlePrecision;
    return std::visit(
        [&](const auto& v) -> std::string {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::monostate>)
                return "";
            else if constexpr (std::is_same_v<T, bool>)
                return v ? "true" : "false";
            else if constexpr (std::is_same_v<T, int64_t> || std::is_same_v<T, uint64_t>)
                return std::to_string(v);
            else if constexpr (std::is_same_v<T, double>)
                return number(v, single);
            else if constexpr (std::is_same_v<T, std::string>)
                return v;
            else
                return number(v[0], single) + "," + number(v[1], single) + "," +
                       number(v[2], single);
        },
        value);
}

std::optional<ParameterValue> parseParameter(const ParameterSpec& spec, std::string_view text,
                                             std::string& error) {
    auto bad = [&]() -> std::optional<ParameterValue> {
        error = spec.name + " must be " + typeError(spec.type) + ", got '" + printable(text) + "'";
        return std::nullopt;
    };
    switch (spec.type) {
        case ParameterType::Bool:
            if (text == "true" || text == "1" || text == "yes" || text == "on") return true;
            if (text == "false" || text == "0" || text == "no" || text == "off") return false;
            return bad();
        case ParameterType::Int: {
            int64_t v;
            if (!parseInt(text, v)) return bad();
            return v;
        }
        case ParameterType::UInt: {
            uint64_t v;
            if (!parseUInt(text, v)) return bad();
            return v;
        }
        case ParameterType::Real: {
            double v;
            if (!parseReal(text, v)) return bad();
            auto r = realOf(spec, v, error);
            if (!r) return std::nullopt;
            return *r;
        }
        case ParameterType::Text:
        case ParameterType::Choice:
            return std::string(text);
        case ParameterType::Rgb: {
            RgbValue rgb;
            size_t start = 0;
            for (int k = 0; k < 3; ++k) {
                size_t comma = k < 2 ? text.find(',', start) : text.size();
                if (comma == std::string_view::npos) return bad();
                if (!parseReal(text.substr(start, comma - start), rgb[size_t(k)])) return bad();
                auto r = realOf(spec, rgb[size_t(k)], error);
                if (!r) return std::nullopt;
                rgb[size_t(k)] = *r;
                start = comma + 1;
            }
            return rgb;
        }
    }
    return bad();
}

std::optional<ParameterValue> coerceParameter(const ParameterSpec& spec,
                                              const ParameterValue& value, std::string& error) {
    if (const auto* text = std::get_if<std::string>(&value))
        return parseParameter(spec, *text, error);
    auto bad = [&]() -> std::optional<ParameterValue> {
        error = spec.name + " must be " + typeError(spec.type) + ", got " +
                printable(formatParameter({}, value));
        return std::nullopt;
    };
    constexpr double kExact = 9007199254740992.0;  // 2^53: every integer below is a double
    switch (spec.type) {
        case ParameterType::Bool:
            if (std::holds_alternative<bool>(value)) return value;
            return bad();
        case ParameterType::Int:
            if (std::holds_alternative<int64_t>(value)) return value;
            if (const auto* u = std::get_if<uint64_t>(&value))
                return *u <= uint64_t(INT64_MAX) ? std::optional<ParameterValue>(int64_t(*u))
                                                 : bad();
            if (const auto* d = std::get_if<double>(&value))
                if (*d == std::floor(*d) && std::abs(*d) <= kExact) return int64_t(*d);
            return bad();
        case ParameterType::UInt:
            if (std::holds_alternative<uint64_t>(value)) return value;
            if (const auto* i = std::get_if<int64_t>(&value))
                return *i >= 0 ? std::optional<ParameterValue>(uint64_t(*i)) : bad();
            if (const auto* d = std::get_if<double>(&value))
                if (*d >= 0 && *d == std::floor(*d) && *d <= kExact) return uint64_t(*d);
            return bad();
        case ParameterType::Real: {
            double v;
            if (const auto* d = std::get_if<double>(&value))
                v = *d;
            else if (const auto* i = std::get_if<int64_t>(&value))
                v = double(*i);
            else if (const auto* u = std::get_if<uint64_t>(&value))
                v = double(*u);
            else
                return bad();
            auto r = realOf(spec, v, error);
            if (!r) return std::nullopt;
            return *r;
        }
        case ParameterType::Text:
        case ParameterType::Choice:
            return bad();
        case ParameterType::Rgb: {
            const auto* rgb = std::get_if<RgbValue>(&value);
            if (!rgb) return bad();
            RgbValue out;
            for (size_t k = 0; k < 3; ++k) {
                auto r = realOf(spec, (*rgb)[k], error);
                if (!r) return std::nullopt;
                out[k] = *r;
            }
            return out;
        }
    }
    return bad();
}

std::string checkParameter(const ParameterSpec& spec, const ParameterValue& value) {
    std::string why;
    std::visit(
        [&](const auto& v) {
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, int64_t> || std::is_same_v<T, uint64_t> ||
                          std::is_same_v<T, double>) {
                if (!std::isfinite(double(v)))
                    why = spec.name + " must be a finite number";
                else if (!inRange(spec, double(v)))
                    why = outside(spec, formatParameter(spec, value));
            } else if constexpr (std::is_same_v<T, RgbValue>) {
                for (double c : v)
                    if (!std::isfinite(c))
                        why = spec.name + " must be finite numbers";
                    else if (!inRange(spec, c) && why.empty())
                        why = outside(spec, formatParameter(spec, value));
            } else if constexpr (std::is_same_v<T, std::string>) {
                if (v.size() > spec.maxLength)
                    why =
                        spec.name + " is longer than " + std::to_string(spec.maxLength) + " bytes";
                else if (spec.type == ParameterType::Choice &&
                         std::find(spec.choices.begin(), spec.choices.end(), v) ==
                             spec.choices.end())
                    why =
                        spec.name + " '" + printable(v) + "' is not one of " + describeRange(spec);
            }
        },
        value);
    if (why.empty() && spec.check) why = spec.check(value);
    return why;
}

std::optional<ParameterValue> acceptParameter(const ParameterSpec& spec,
                                              const ParameterValue& given, std::string& error) {
    if (std::holds_alternative<std::monostate>(given)) return spec.defaultValue;
    std::optional<ParameterValue> v = coerceParameter(spec, given, error);
    if (!v) return std::nullopt;
    error = checkParameter(spec, *v);
    if (!error.empty()) return std::nullopt;
    return v;
}

std::string describeRange(const ParameterSpec& spec) {
    if (spec.type == ParameterType::Choice) {
        std::string out;
        for (const auto& c : spec.choices) out += (out.empty() ? "" : " | ") + c;
        return out;
    }
    if (spec.type == ParameterType::Text)
        return fmt::format("text of at most {} bytes", spec.maxLength);
    if (spec.type == ParameterType::Bool) return "true | false";
    bool single = spec.singlePrecision;
    if (spec.min && spec.max)
        return fmt::format("{}{}, {}]", spec.minExclusive ? "(" : "[", number(*spec.min, single),
                           number(*spec.max, single));
    if (spec.min)
        return fmt::format("{} {}", spec.minExclusive ? ">" : ">=", number(*spec.min, single));
    if (spec.max) return fmt::format("<= {}", number(*spec.max, single));
    return "any";
}

const ParameterSpec* findParameter(const std::vector<ParameterSpec>& specs, std::string_view name) {
    for (const auto& s : specs)
        if (s.name == name) return &s;
    return nullptr;
}

}  // namespace partita
