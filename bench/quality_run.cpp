#include "quality_run.h"

#include <cstdio>

#include "eval/spread.h"
#include "eval_render.h"
#include "frontend/progress_bar.h"

namespace partita::eval {

namespace {

/// RMSE and relMSE of `layer` over the seeds where the render had it.
struct LayerSpread {
    Spread rmse, relMse;
    int seeds = 0;
};

LayerSpread layerSpread(const AlgorithmRun& run, const std::string& layer) {
    std::vector<double> rmse, rel;
    for (const auto& r : run.runs)
        for (const auto& e : r.errors)
            if (e.layer == layer) {
                rmse.push_back(e.rmse);
                rel.push_back(e.relMse);
            }
    return {spreadOf(rmse), spreadOf(rel), int(rmse.size())};
}

template <class F>
Spread over(const AlgorithmRun& run, F figure) {
    std::vector<double> v;
    for (const auto& r : run.runs) v.push_back(figure(r));
    return spreadOf(v);
}

double unitsPerPixel(const AlgorithmRun& run) {
    return over(run, [](const SeedRun& r) { return r.unitsPerPixel; }).mean;
}

double rate(const AlgorithmRun& run) {
    double pixels = double(run.settings.width) * run.settings.height;
    return over(run, [&](const SeedRun& r) { return r.unitsPerPixel * pixels / r.wallSeconds; })
        .mean;
}

std::vector<Statistics> statistics(const AlgorithmRun& run) {
    std::vector<Statistics> v;
    for (const auto& r : run.runs) v.push_back(r.stats);
    return v;
}

/// Seconds of sampling per sample or mutation, mean over the seeds that report it.
std::optional<double> meanSecondsPerUnit(const AlgorithmRun& run) {
    double pixels = double(run.settings.width) * run.settings.height;
    std::vector<double> v;
    for (const auto& r : run.runs)
        if (auto s = secondsPerUnit(r.stats, r.unitsPerPixel, pixels)) v.push_back(*s);
    if (v.empty()) return std::nullopt;
    return spreadOf(v).mean;
}

std::optional<double> raysPerSecond(const AlgorithmRun& run) {
    Statistics mean = meanStatistics(statistics(run));
    auto it = mean.find("rays_per_second");
    if (it == mean.end()) return std::nullopt;
    return it->second;
}

std::optional<double> ratio(std::optional<double> a, std::optional<double> b) {
    if (!a || !b || !(*b > 0)) return std::nullopt;
    return *a / *b;
}

nlohmann::json orNull(std::optional<double> v) { return v ? nlohmann::json(*v) : nlohmann::json(); }

std::string formatted(const char* format, std::optional<double> v) {
    if (!v) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, format, *v);
    return buf;
}

std::optional<double> acceptance(const AlgorithmRun& run) {
    std::vector<double> v;
    for (const auto& r : run.runs)
        if (r.acceptance) v.push_back(*r.acceptance);
    if (v.empty()) return std::nullopt;
    return spreadOf(v).mean;
}

const char* budgetField(BudgetKind k) {
    return k == BudgetKind::SamplesPerPixel     ? "spp"
           : k == BudgetKind::MutationsPerPixel ? "mpp"
                                                : "seconds";
}

nlohmann::json layersJson(const AlgorithmRun& run, const std::vector<std::string>& layerOrder,
                          const ReferenceErrors& referenceErrors) {
    nlohmann::json layers = nlohmann::json::array();
    for (const auto& name : layerOrder) {
        LayerSpread s = layerSpread(run, name);
        if (s.seeds == 0) continue;
        nlohmann::json l = {{"layer", name},
                            {"seeds", s.seeds},
                            {"rmse_mean", s.rmse.mean},
                            {"rmse_std", s.rmse.std},
                            {"relmse_mean", s.relMse.mean},
                            {"relmse_std", s.relMse.std}};
        auto ref = referenceErrors.find(name);
        l["reference_rmse"] =
            ref == referenceErrors.end() ? nlohmann::json() : nlohmann::json(ref->second.rmse);
        layers.push_back(l);
    }
    return layers;
}

std::string meanStd(const Spread& s) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.4g +- %.2g", s.mean, s.std);
    return buf;
}

void printAlgorithmRow(const AlgorithmRun& run) {
    LayerSpread combined = layerSpread(run, kCombinedLayerName);
    std::string accText = formatted("%.3f", acceptance(run));
    std::string unit = run.runs.empty() ? "" : run.runs.front().unit;
    std::string budget = budgetText(run.settings);
    if (run.settings.budgetKind == BudgetKind::Seconds && !run.runs.empty())
        budget += " = " + std::to_string(int(unitsPerPixel(run) + 0.5)) +
                  (run.runs.front().unit == "samples" ? " spp" : " mpp");
    std::printf("%-12s %-16s %5zu  %-20s %-20s %8.2f  %9s %-11s %6s  %7.1f (+%.1f)%s\n",
                run.algorithm.c_str(), budget.c_str(), run.runs.size(),
                meanStd(combined.rmse).c_str(), meanStd(combined.relMse).c_str(),
                meanWallSeconds(run), humanCount(rate(run)).c_str(), (unit + "/s").c_str(),
                accText.c_str(), run.peakRssMb, run.rssIncreaseMb,
                run.peakPerAlgorithm ? "" : " *");
}

/// The share of the wall time an algorithm spent in its bootstrap (mlt), mean over seeds.
std::optional<double> bootstrapShare(const AlgorithmRun& run) {
    std::vector<double> v;
    for (const auto& r : run.runs) {
        auto b = r.stats.find("bootstrap_seconds");
        if (b != r.stats.end() && r.wallSeconds > 0) v.push_back(b->second / r.wallSeconds);
    }
    if (v.empty()) return std::nullopt;
    return spreadOf(v).mean;
}

/// Cost per sample or mutation and rays/s, each also relative to the first algorithm's.
void printCostRows(const std::vector<AlgorithmRun>& runs) {
    const AlgorithmRun& base = runs.front();
    std::printf(
        "\nsampling cost (render_seconds per sample or mutation: pt/bdpt passes, mlt "
        "chains) and rays/s, relative to %s\n",
        base.algorithm.c_str());
    std::string relative = "x " + base.algorithm;
    std::printf("%-12s %14s %10s %10s %12s %10s %10s\n", "algorithm", "units/s", "us/unit",
                relative.c_str(), "rays/s", relative.c_str(), "bootstrap");
    for (const auto& r : runs) {
        auto cost = meanSecondsPerUnit(r), rays = raysPerSecond(r);
        auto share = bootstrapShare(r);
        std::printf("%-12s %14s %10s %10s %12s %10s %10s\n", r.algorithm.c_str(),
                    cost ? humanCount(1 / *cost).c_str() : "-",
                    formatted("%.4g", cost ? std::optional(*cost * 1e6) : std::nullopt).c_str(),
                    formatted("%.3g", ratio(cost, meanSecondsPerUnit(base))).c_str(),
                    rays ? humanCount(*rays).c_str() : "-",
                    formatted("%.3g", ratio(rays, raysPerSecond(base))).c_str(),
                    share ? (formatted("%.0f", *share * 100) + "%").c_str() : "-");
    }
}

/// Acceptance per mutation type, mean over the seeds that proposed it, for the algorithms that
/// report mutation types.
void printAcceptanceRows(const std::vector<AlgorithmRun>& runs) {
    bool header = false;
    for (const auto& r : runs) {
        auto perMutation = acceptancePerMutation(statistics(r));
        if (perMutation.empty()) continue;
        if (!header) std::printf("\nacceptance per mutation type, mean over seeds\n");
        header = true;
        std::printf("%-12s", r.algorithm.c_str());
        for (const auto& [name, a] : perMutation)
            std::printf("  %s %s", name.c_str(), formatted("%.3f", a).c_str());
        std::printf("\n");
    }
}

void printLayerRows(const std::vector<AlgorithmRun>& runs,
                    const std::vector<std::string>& layerOrder,
                    const ReferenceErrors& referenceErrors, size_t tableLayers) {
    std::printf("\nRMSE per layer, mean +- std over seeds (ref: the reference's own RMSE)\n");
    std::printf("%-20s %10s", "layer", "ref");
    for (const auto& r : runs) std::printf("  %-20s", r.algorithm.c_str());
    std::printf("\n");
    size_t shown = 0;
    bool partial = false;
    for (const auto& name : layerOrder) {
        if (shown++ == tableLayers + 1) {  // + 1: "combined" is not a type layer
            std::printf("... %zu more layers in the JSON\n", layerOrder.size() - shown + 1);
            break;
        }
        auto ref = referenceErrors.find(name);
        char refText[32] = "-";
        if (ref != referenceErrors.end())
            std::snprintf(refText, sizeof refText, "%.4g", ref->second.rmse);
        std::printf("%-20s %10s", name.c_str(), refText);
        for (const auto& r : runs) {
            LayerSpread s = layerSpread(r, name);
            std::string text = s.seeds ? meanStd(s.rmse) : "-";
            if (s.seeds && size_t(s.seeds) < r.runs.size()) {
                text += " *";  // the renders of some seeds did not keep this type
                partial = true;
            }
            std::printf("  %-20s", text.c_str());
        }
        std::printf("\n");
    }
    if (partial)
        std::printf("* over the seeds whose render kept this type among its --layers largest\n");
}

}  // namespace

double meanWallSeconds(const AlgorithmRun& run) {
    return over(run, [](const SeedRun& r) { return r.wallSeconds; }).mean;
}

nlohmann::json resultJson(const AlgorithmRun& run, const AlgorithmRun& baseline,
                          const std::vector<std::string>& layerOrder,
                          const ReferenceErrors& referenceErrors) {
    LayerSpread combined = layerSpread(run, kCombinedLayerName);
    Spread seconds = over(run, [](const SeedRun& r) { return r.wallSeconds; });
    nlohmann::json j;
    j["algorithm"] = run.algorithm;
    j[budgetField(run.settings.budgetKind)] = run.settings.budget;
    j["seeds"] = run.runs.size();
    j["rmse_mean"] = combined.rmse.mean;
    j["rmse_std"] = combined.rmse.std;
    j["relmse_mean"] = combined.relMse.mean;
    j["relmse_std"] = combined.relMse.std;
    j["seconds_mean"] = seconds.mean;
    j["seconds_std"] = seconds.std;
    j["rate"] = rate(run);
    j["rate_unit"] = run.runs.empty() ? "" : run.runs.front().unit + "/s";
    j["units_per_pixel_mean"] = unitsPerPixel(run);
    j["acceptance"] = orNull(acceptance(run));
    j["peak_rss_mb"] = run.peakRssMb;
    j["rss_increase_mb"] = run.rssIncreaseMb;
    j["peak_rss_per_algorithm"] = run.peakPerAlgorithm;
    j["baseline"] = baseline.algorithm;
    j["seconds_per_unit"] = orNull(meanSecondsPerUnit(run));
    j["cost_per_unit_relative"] =
        orNull(ratio(meanSecondsPerUnit(run), meanSecondsPerUnit(baseline)));
    j["rays_per_second"] = orNull(raysPerSecond(run));
    j["rays_per_second_relative"] = orNull(ratio(raysPerSecond(run), raysPerSecond(baseline)));
    j["bootstrap_share"] = orNull(bootstrapShare(run));
    nlohmann::json perMutation = nlohmann::json::object();
    for (const auto& [name, a] : acceptancePerMutation(statistics(run)))
        perMutation[name] = orNull(a);
    j["acceptance_per_mutation"] = perMutation;
    j["statistics_mean"] = meanStatistics(statistics(run));
    nlohmann::json perSeed = nlohmann::json::array();
    for (const auto& r : run.runs)
        perSeed.push_back({{"seed", r.seed},
                           {"rmse", r.errors.front().rmse},
                           {"relmse", r.errors.front().relMse},
                           {"seconds", r.wallSeconds},
                           {"statistics", r.stats}});
    j["per_seed"] = perSeed;
    j["layers"] = layersJson(run, layerOrder, referenceErrors);
    return j;
}

void printQualityTables(const std::vector<AlgorithmRun>& runs,
                        const std::vector<std::string>& layerOrder,
                        const ReferenceErrors& referenceErrors, size_t tableLayers) {
    std::printf("%-12s %-16s %5s  %-20s %-20s %8s  %21s %6s  %s\n", "algorithm", "budget", "seeds",
                "RMSE", "relMSE", "seconds", "rate", "accept", "peak RSS MB (+run)");
    for (const auto& r : runs) printAlgorithmRow(r);
    bool lifetime = false;
    for (const auto& r : runs) lifetime = lifetime || !r.peakPerAlgorithm;
    if (lifetime) std::printf("* the process's lifetime peak (the peak could not be reset)\n");
    if (!runs.empty()) printCostRows(runs);
    printAcceptanceRows(runs);
    printLayerRows(runs, layerOrder, referenceErrors, tableLayers);
}

}  // namespace partita::eval
