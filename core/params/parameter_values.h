// Parameter values by name: what a job gives (a part) or what it runs with (every declared
// parameter, defaults filled in: params/job_parameters.h).
#pragma once

#include <map>
#include <string>
#include <type_traits>

#include "params/parameter.h"

namespace partita {

class ParameterValues {
  public:
    using Map = std::map<std::string, ParameterValue>;

    /// Sets `name` to `value`, held in the variant's own type: any signed integer as int64_t,
    /// any unsigned one as uint64_t, any floating point as double, character strings as text.
    template <class T>
    ParameterValues& set(const std::string& name, T value) {
        values_[name] = toValue(value);
        return *this;
    }
    ParameterValues& setValue(const std::string& name, ParameterValue value) {
        values_[name] = std::move(value);
        return *this;
    }
    void erase(const std::string& name) { values_.erase(name); }

    const ParameterValue* find(const std::string& name) const {
        auto it = values_.find(name);
        return it == values_.end() ? nullptr : &it->second;
    }
    bool has(const std::string& name) const { return values_.count(name) > 0; }
    bool empty() const { return values_.empty(); }
    size_t size() const { return values_.size(); }
    Map::const_iterator begin() const { return values_.begin(); }
    Map::const_iterator end() const { return values_.end(); }
    bool operator==(const ParameterValues&) const = default;

    template <class T>
    static ParameterValue toValue(T value) {
        if constexpr (std::is_same_v<T, ParameterValue> || std::is_same_v<T, bool> ||
                      std::is_same_v<T, RgbValue> || std::is_same_v<T, std::string>)
            return value;
        else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>)
            return int64_t(value);
        else if constexpr (std::is_integral_v<T>)
            return uint64_t(value);
        else if constexpr (std::is_floating_point_v<T>)
            return double(value);
        else
            return std::string(value);
    }

  private:
    Map values_;
};

}  // namespace partita
