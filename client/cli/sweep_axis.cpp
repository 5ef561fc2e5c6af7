#include "cli/sweep_axis.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <set>

#include "cli/errors.h"

namespace partita::cli {

namespace {

enum class Kind { Int, UInt, Real };

struct Param {
    const char* name;
    Kind kind;
};

constexpr Param kParams[] = {
    {"y", Kind::Int},     {"radius", Kind::Real}, {"k", Kind::Int},        {"epsilon", Kind::Real},
    {"spp", Kind::Real},  {"mpp", Kind::Real},    {"seconds", Kind::Real}, {"max-depth", Kind::Int},
    {"seed", Kind::UInt}, {"width", Kind::Int},   {"height", Kind::Int},
};

const Param* findParam(const std::string& name) {
    for (const auto& p : kParams)
        if (name == p.name) return &p;
    return nullptr;
}

bool parseNumber(const std::string& s, Kind kind, double* real, long long* integer,
                 unsigned long long* uinteger) {
    if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return false;
    char* end = nullptr;
    errno = 0;
    switch (kind) {
        case Kind::Real:
            *real = std::strtod(s.c_str(), &end);
            break;
        case Kind::Int:
            *integer = std::strtoll(s.c_str(), &end, 10);
            break;
        case Kind::UInt:
            if (s.front() == '-') return false;
            *uinteger = std::strtoull(s.c_str(), &end, 10);
            break;
    }
    if (errno != 0 || end != s.c_str() + s.size()) return false;
    if (kind == Kind::Real && !std::isfinite(*real)) return false;
    if (kind == Kind::Int && (*integer < INT32_MIN || *integer > INT32_MAX)) return false;
    return true;
}

}  // namespace

std::string sweepParameterNames() {
    std::string out;
    for (const auto& p : kParams) out += (out.empty() ? "" : ", ") + std::string(p.name);
    return out;
}

SweepAxis parseSweepAxis(const std::string& text) {
    auto bad = [&](const std::string& why) -> SweepAxis {
        throw CliError("bad --sweep '" + text + "': " + why +
                       " (expected NAME=V1,V2,... with NAME one of " + sweepParameterNames() + ")");
    };
    size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) return bad("no NAME=");
    SweepAxis axis;
    axis.name = text.substr(0, eq);
    for (char& c : axis.name)
        if (c == '_') c = '-';
    const Param* param = findParam(axis.name);
    if (!param) return bad("unknown parameter '" + axis.name + "'");
    std::string list = text.substr(eq + 1);
    std::set<std::string> seen;
    size_t start = 0;
    while (true) {
        size_t comma = list.find(',', start);
        std::string v =
            list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        double r;
        long long i;
        unsigned long long u;
        if (v.empty()) return bad("empty value");
        if (!parseNumber(v, param->kind, &r, &i, &u))
            return bad("'" + v + "' is not " +
                       (param->kind == Kind::Real ? "a number" : "a whole number"));
        if (!seen.insert(v).second) return bad("value '" + v + "' repeats");
        axis.values.push_back(v);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return axis;
}

void applySweepValue(partita::v1::JobSpec& spec, const std::string& name,
                     const std::string& value) {
    const Param* param = findParam(name);
    double r = 0;
    long long i = 0;
    unsigned long long u = 0;
    if (!param || !parseNumber(value, param->kind, &r, &i, &u))
        throw CliError("bad sweep value " + name + "=" + value);
    auto budget = [&](partita::v1::BudgetKind kind) {
        spec.mutable_budget()->set_kind(kind);
        spec.mutable_budget()->set_amount(r);
    };
    if (name == "y")
        spec.set_y(int32_t(i));
    else if (name == "radius")
        spec.set_radius(float(r));
    else if (name == "k")
        spec.set_k(int32_t(i));
    else if (name == "epsilon")
        spec.set_epsilon(float(r));
    else if (name == "spp")
        budget(partita::v1::BUDGET_KIND_SAMPLES_PER_PIXEL);
    else if (name == "mpp")
        budget(partita::v1::BUDGET_KIND_MUTATIONS_PER_PIXEL);
    else if (name == "seconds")
        budget(partita::v1::BUDGET_KIND_SECONDS);
    else if (name == "max-depth")
        spec.set_max_depth(int32_t(i));
    else if (name == "seed")
        spec.set_seed(u);
    else if (name == "width")
        spec.set_width(int32_t(i));
    else if (name == "height")
        spec.set_height(int32_t(i));
}

}  // namespace partita::cli
