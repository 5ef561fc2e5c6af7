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
    auto acc = acceptance(run);
    char accText[16] = "-";
    if (acc) std::snprintf(accText, sizeof accText, "%.3f", *acc);
    std::string unit = run.runs.empty() ? "" : run.runs.front().unit;
    std::string budget = budgetText(run.settings);
    if (run.settings.budgetKind == BudgetKind::Seconds && !run.runs.empty())
        budget += " = " + std::to_string(int(unitsPerPixel(run) + 0.5)) +
                  (run.runs.front().unit == "samples" ? " spp" : " mpp");
    std::printf("%-12s %-16s %5zu  %-20s %-20s %8.2f  %9s %-11s %6s  %7.1f (+%.1f)%s\n",
                run.algorithm.c_str(), budget.c_str(), run.runs.size(),
                meanStd(combined.rmse).c_str(), meanStd(combined.relMse).c_str(),
                meanWallSeconds(run), humanCount(rate(run)).c_str(), (unit + "/s").c_str(), accText,
                run.peakRssMb, run.rssIncreaseMb, run.peakPerAlgorithm ? "" : " *");
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

nlohmann::json resultJson(const AlgorithmRun& run, const std::vector<std::string>& layerOrder,
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
    auto acc = acceptance(run);
    j["acceptance"] = acc ? nlohmann::json(*acc) : nlohmann::json();
    j["peak_rss_mb"] = run.peakRssMb;
    j["rss_increase_mb"] = run.rssIncreaseMb;
    j["peak_rss_per_algorithm"] = run.peakPerAlgorithm;
    nlohmann::json perSeed = nlohmann::json::array();
    for (const auto& r : run.runs)
        perSeed.push_back({{"seed", r.seed},
                           {"rmse", r.errors.front().rmse},
                           {"relmse", r.errors.front().relMse},
                           {"seconds", r.wallSeconds}});
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
    printLayerRows(runs, layerOrder, referenceErrors, tableLayers);
}

}  // namespace partita::eval
