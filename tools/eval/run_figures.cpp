#include "eval/run_figures.h"

namespace partita::eval {

namespace {

constexpr const char* kAcceptance = "acceptance_";
constexpr const char* kProposed = "proposed_";

std::optional<double> find(const Statistics& s, const std::string& key) {
    auto it = s.find(key);
    if (it == s.end()) return std::nullopt;
    return it->second;
}

/// The mutation types of a render: the names after "acceptance_".
std::vector<std::string> mutationNames(const Statistics& s) {
    std::vector<std::string> names;
    for (const auto& [key, value] : s)
        if (key.rfind(kAcceptance, 0) == 0)
            names.push_back(key.substr(std::string(kAcceptance).size()));
    return names;
}

}  // namespace

Statistics meanStatistics(const std::vector<Statistics>& perSeed) {
    Statistics sum, count;
    for (const auto& s : perSeed)
        for (const auto& [key, value] : s) {
            sum[key] += value;
            count[key] += 1;
        }
    for (auto& [key, value] : sum) value /= count[key];
    return sum;
}

std::optional<double> secondsPerUnit(const Statistics& stats, double unitsPerPixel, double pixels) {
    auto seconds = find(stats, "render_seconds");
    double units = unitsPerPixel * pixels;
    if (!seconds || !(units > 0)) return std::nullopt;
    return *seconds / units;
}

std::map<std::string, std::optional<double>> acceptancePerMutation(
    const std::vector<Statistics>& perSeed) {
    std::map<std::string, std::pair<double, int>> sums;  // sum of acceptances, seeds
    for (const auto& s : perSeed)
        for (const auto& name : mutationNames(s)) {
            auto& [sum, seeds] = sums[name];
            auto proposed = find(s, kProposed + name);
            if (proposed && !(*proposed > 0)) continue;
            sum += s.at(kAcceptance + name);
            ++seeds;
        }
    std::map<std::string, std::optional<double>> out;
    for (const auto& [name, sum] : sums)
        out[name] = sum.second ? std::optional<double>(sum.first / sum.second) : std::nullopt;
    return out;
}

std::optional<double> overallAcceptance(const Statistics& stats) {
    if (auto a = find(stats, "acceptance")) return a;
    double accepted = 0, proposed = 0;
    for (const auto& name : mutationNames(stats)) {
        double p = find(stats, kProposed + name).value_or(0);
        accepted += p * stats.at(kAcceptance + name);
        proposed += p;
    }
    if (!(proposed > 0)) return std::nullopt;
    return accepted / proposed;
}

}  // namespace partita::eval
