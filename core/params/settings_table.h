// Declared parameters bound to the fields of a settings struct S. The declaration takes its type
// and its default from the field and from S{} (the struct's initialisers are the one place a
// default is written); `resolve` is the one function that turns a job's values into an S.
//
//   SettingsTable<GuidedSettings> table;
//   table.add({.name = "radius", .help = "R: ...", .unit = "pixels", .min = 0,
//              .max = 4096, .minExclusive = true}, &GuidedSettings::radius);
#pragma once

#include <stdexcept>
#include <type_traits>
#include <vector>

#include "params/parameter.h"
#include "params/parameter_values.h"

namespace partita {

namespace detail {

template <class T>
constexpr ParameterType parameterTypeOf() {
    if constexpr (std::is_same_v<T, bool>)
        return ParameterType::Bool;
    else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>)
        return ParameterType::Int;
    else if constexpr (std::is_integral_v<T>)
        return ParameterType::UInt;
    else if constexpr (std::is_floating_point_v<T>)
        return ParameterType::Real;
    else if constexpr (std::is_same_v<T, std::string>)
        return ParameterType::Text;
    else {
        static_assert(std::is_same_v<T, std::array<float, 3>> || std::is_same_v<T, RgbValue>,
                      "a parameter field is a bool, integer, float, string or RGB triple");
        return ParameterType::Rgb;
    }
}

template <class T>
ParameterValue valueOf(const T& field) {
    if constexpr (std::is_same_v<T, std::array<float, 3>>)
        return RgbValue{field[0], field[1], field[2]};
    else
        return ParameterValues::toValue(field);
}

/// Writes a value already in the field's parameter type (coerceParameter) into the field.
template <class T>
void assign(T& field, const ParameterValue& value) {
    if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::string>)
        field = std::get<T>(value);
    else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>)
        field = T(std::get<int64_t>(value));
    else if constexpr (std::is_integral_v<T>)
        field = T(std::get<uint64_t>(value));
    else if constexpr (std::is_floating_point_v<T>)
        field = T(std::get<double>(value));
    else {
        const RgbValue& rgb = std::get<RgbValue>(value);
        for (size_t k = 0; k < 3; ++k) field[k] = typename T::value_type(rgb[k]);
    }
}

}  // namespace detail

template <class S>
class SettingsTable {
  public:
    using Getter = std::function<ParameterValue(const S&)>;
    using Setter = std::function<void(S&, const ParameterValue&)>;

    /// Declares `spec` for a field of S (or of a base of S); a string field with choices is a
    /// Choice.
    template <class T, class C>
    SettingsTable& add(ParameterSpec spec, T C::*field) {
        static_assert(std::is_base_of_v<C, S>, "the field belongs to S or a base of S");
        spec.type = detail::parameterTypeOf<T>();
        if (spec.type == ParameterType::Text && !spec.choices.empty())
            spec.type = ParameterType::Choice;
        spec.singlePrecision = std::is_same_v<T, float> || std::is_same_v<T, std::array<float, 3>>;
        return add(
            std::move(spec), [field](const S& s) { return detail::valueOf(s.*field); },
            [field](S& s, const ParameterValue& v) { detail::assign(s.*field, v); });
    }

    /// Declares `spec` (its type set) with its own reading and writing of S: a field inside a
    /// member, or a parameter that may be unset (get returns monostate, set receives it).
    SettingsTable& add(ParameterSpec spec, Getter get, Setter set) {
        spec.defaultValue = get(S{});
        entries_.push_back({spec, std::move(get), std::move(set)});
        specs_.push_back(std::move(spec));
        return *this;
    }

    /// Appends every declaration of `other`, a table of a base of S (shared parameters).
    template <class B>
    SettingsTable& addAll(const SettingsTable<B>& other) {
        static_assert(std::is_base_of_v<B, S>, "other binds a base of S");
        for (const auto& e : other.entries())
            add(
                e.spec, [get = e.get](const S& s) { return get(static_cast<const B&>(s)); },
                [set = e.set](S& s, const ParameterValue& v) { set(static_cast<B&>(s), v); });
        return *this;
    }

    const std::vector<ParameterSpec>& specs() const { return specs_; }

    /// The binding of the parameter called `name`, or null.
    const auto* find(std::string_view name) const {
        for (const auto& e : entries_)
            if (e.spec.name == name) return &e;
        return static_cast<const Entry*>(nullptr);
    }

    /// `settings` with every declared parameter that `values` gives applied (converted to the
    /// declared type and checked); names it does not declare are left to the caller. Throws
    /// std::invalid_argument with checkParameter's line for a bad value.
    S resolve(const ParameterValues& values, S settings = {}) const {
        for (const auto& e : entries_) {
            const ParameterValue* given = values.find(e.spec.name);
            if (!given) continue;
            std::string error;
            std::optional<ParameterValue> v = acceptParameter(e.spec, *given, error);
            if (!v) throw std::invalid_argument(error);
            e.set(settings, *v);
        }
        return settings;
    }

    /// Every declared parameter's value in `settings` (unset ones as monostate).
    ParameterValues values(const S& settings) const {
        ParameterValues out;
        for (const auto& e : entries_) out.setValue(e.spec.name, e.get(settings));
        return out;
    }

    struct Entry {
        ParameterSpec spec;
        Getter get;
        Setter set;
    };
    const std::vector<Entry>& entries() const { return entries_; }

  private:
    std::vector<Entry> entries_;
    std::vector<ParameterSpec> specs_;
};

}  // namespace partita
