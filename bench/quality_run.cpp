#include "quality_run.h"

#include <algorithm>
#include <cstdio>

#include "eval/spread.h"
#include "eval_render.h"
#include "frontend/progress_bar.h"
#include "partition/partition.h"

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

/// One partition of a partitioned algorithm over the seeds whose render had it (the pre-pass,
/// and so the K types, depends on the seed): its statistics P(i), b_i, acceptance and
/// mutations, and its error against its reference (eval/partition_error.h).
struct PartitionFigures {
    std::string layer;
    int seeds = 0;
    bool inReference = true;     // in every seed's reference (a type the reference lacks: false)
    bool ownStatistics = false;  // P(i), b_i ... are the algorithm's (else they are unknown)
    Spread p, b, acceptance, mutations, rmse, relMse, share;
};

std::vector<PartitionFigures> partitionFigures(const AlgorithmRun& run) {
    std::vector<std::string> order;  // as the first seeds list them, the complement last
    for (const auto& r : run.runs)
        for (const auto& e : r.partitions)
            if (std::find(order.begin(), order.end(), e.layer) == order.end())
                order.push_back(e.layer);
    std::stable_partition(order.begin(), order.end(),
                          [](const std::string& n) { return n != kComplementLabel; });
    std::vector<PartitionFigures> out;
    for (const auto& name : order) {
        PartitionFigures f;
        f.layer = name;
        std::vector<double> p, b, acc, mutations, rmse, rel, share;
        for (const auto& r : run.runs)
            for (size_t g = 0; g < r.partitions.size(); ++g) {
                const PartitionError& e = r.partitions[g];
                if (e.layer != name) continue;
                f.inReference = f.inReference && e.inReference;
                std::string key = "partition_" + std::to_string(g) + "_";
                auto stat = [&](const char* what, std::vector<double>& v) {
                    if (auto it = r.stats.find(key + what); it != r.stats.end())
                        v.push_back(it->second);
                };
                stat("p", p);
                stat("b", b);
                stat("acceptance", acc);
                stat("mutations", mutations);
                rmse.push_back(e.rmse);
                rel.push_back(e.relMse);
                share.push_back(e.share);
            }
        f.seeds = int(rmse.size());
        f.ownStatistics = !p.empty();
        f.p = spreadOf(p);
        f.b = spreadOf(b);
        f.acceptance = spreadOf(acc);
        f.mutations = spreadOf(mutations);
        f.rmse = spreadOf(rmse);
        f.relMse = spreadOf(rel);
        f.share = spreadOf(share);
        out.push_back(f);
    }
    return out;
}

/// The sum of the partitions' shares of the squared error, mean over seeds (1 without cross
/// terms); null without partitions.
std::optional<double> shareSum(const AlgorithmRun& run) {
    std::vector<double> v;
    for (const auto& r : run.runs) {
        if (r.partitions.empty()) continue;
        double sum = 0;
        for (const auto& e : r.partitions) sum += e.share;
        v.push_back(sum);
    }
    if (v.empty()) return std::nullopt;
    return spreadOf(v).mean;
}

nlohmann::json partitionsJson(const AlgorithmRun& run, const ReferenceErrors& referenceErrors) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& f : partitionFigures(run)) {
        auto ref = referenceErrors.find(f.layer);
        auto own = [&](double v) { return f.ownStatistics ? nlohmann::json(v) : nlohmann::json(); };
        out.push_back(
            {{"layer", f.layer},
             {"seeds", f.seeds},
             {"in_reference", f.inReference},
             {"p", own(f.p.mean)},
             {"p_std", own(f.p.std)},
             {"b", own(f.b.mean)},
             {"b_std", own(f.b.std)},
             {"acceptance", own(f.acceptance.mean)},
             {"acceptance_std", own(f.acceptance.std)},
             {"mutations_mean", own(f.mutations.mean)},
             {"rmse_mean", f.rmse.mean},
             {"rmse_std", f.rmse.std},
             {"relmse_mean", f.relMse.mean},
             {"relmse_std", f.relMse.std},
             {"error_share_mean", f.share.mean},
             {"error_share_std", f.share.std},
             {"reference_rmse", f.layer == kComplementLabel || ref == referenceErrors.end()
                                    ? nlohmann::json()
                                    : nlohmann::json(ref->second.rmse)}});
    }
    return out;
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

/// Per partition of each partitioned algorithm: P(i), b_i, acceptance, its RMSE against its own
/// reference and its share of the combined image's squared error; the same errors of the
/// algorithms measured on a partitioned algorithm's partitions (decomposeIntoPartitions).
void printPartitionRows(const std::vector<AlgorithmRun>& runs,
                        const ReferenceErrors& referenceErrors) {
    for (const auto& run : runs) {
        auto sum = shareSum(run);
        if (!sum) continue;
        std::string prepass;
        const auto& labels = run.runs.front().labels;
        if (auto it = labels.find("prepass"); it != labels.end()) prepass = it->second;
        if (run.partitionsOf.empty())
            std::printf(
                "\n%s per partition, mean +- std over the seeds that had it (pre-pass %s)\n",
                run.algorithm.c_str(), prepass.c_str());
        else
            std::printf(
                "\n%s on the partitions of %s's render of the same seed (its type layers; "
                "complement: its combined minus them;\nleft out: a seed whose render merged one "
                "of the types into 'other')\n",
                run.algorithm.c_str(), run.partitionsOf.c_str());
        std::printf(
            "RMSE against the partition's reference (the type's layer; complement: combined "
            "minus the K types' layers);\nshare: its squared error over the combined image's "
            "(the shares sum to %.3f, not 1: cross terms between partitions)\n",
            *sum);
        std::printf("%-20s %5s %8s  %-20s %7s  %-20s %10s %7s\n", "partition", "seeds", "P(i)",
                    "b_i", "accept", "RMSE", "ref", "share");
        bool missing = false;
        for (const auto& f : partitionFigures(run)) {
            auto ref = referenceErrors.find(f.layer);
            char refText[32] = "-";
            if (f.layer != kComplementLabel && ref != referenceErrors.end())
                std::snprintf(refText, sizeof refText, "%.4g", ref->second.rmse);
            std::string name = f.layer + (f.inReference ? "" : " !");
            missing = missing || !f.inReference;
            std::string p = "-", b = "-", acc = "-";
            if (f.ownStatistics) {
                p = formatted("%.4f", f.p.mean);
                b = meanStd(f.b);
                acc = formatted("%.3f", f.acceptance.mean);
            }
            std::printf("%-20s %5d %8s  %-20s %7s  %-20s %10s %7.3f\n", name.c_str(), f.seeds,
                        p.c_str(), b.c_str(), acc.c_str(), meanStd(f.rmse).c_str(), refText,
                        f.share.mean);
        }
        if (missing)
            std::printf(
                "! a type the reference has no layer of (compared with black); the complement "
                "when the reference may hold such a type in its 'other'\n");
    }
}

/// The daemon's memory estimate of one job against what the renders here added.
void printEstimateRows(const std::vector<AlgorithmRun>& runs) {
    bool any = false;
    for (const auto& r : runs) any = any || r.estimateMb.has_value();
    if (!any) return;
    std::printf(
        "\njob memory estimate (server/job_memory.h) against the measured peak increase here "
        "(in-process, no previews)\n");
    for (const auto& r : runs)
        if (r.estimateMb)
            std::printf("%-12s estimate %8.1f MB  measured +%.1f MB  (%s)\n", r.algorithm.c_str(),
                        *r.estimateMb, r.rssIncreaseMb, r.estimateBreakdown.c_str());
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
    // Chains that moved in none of the last half of their mutations, and chains that never left
    // their start's type, per seed (MCMC only).
    nlohmann::json stuck = nlohmann::json::array();
    for (const Statistics& st : statistics(run))
        if (auto it = st.find("stuck_chains"); it != st.end()) stuck.push_back(it->second);
    j["stuck_chains"] = stuck;
    nlohmann::json bound = nlohmann::json::array();
    for (const Statistics& st : statistics(run))
        if (auto it = st.find("type_bound_chains"); it != st.end()) bound.push_back(it->second);
    j["type_bound_chains"] = bound;
    j["job_memory_estimate_mb"] = orNull(run.estimateMb);
    j["job_memory_estimate_breakdown"] = run.estimateBreakdown;
    nlohmann::json perSeed = nlohmann::json::array();
    for (const auto& r : run.runs) {
        nlohmann::json seed = {{"seed", r.seed},
                               {"rmse", r.errors.front().rmse},
                               {"relmse", r.errors.front().relMse},
                               {"seconds", r.wallSeconds},
                               {"statistics", r.stats},
                               {"labels", r.labels}};
        if (!r.partitions.empty()) {
            nlohmann::json parts = nlohmann::json::array();
            for (const auto& e : r.partitions)
                parts.push_back({{"layer", e.layer},
                                 {"rmse", e.rmse},
                                 {"relmse", e.relMse},
                                 {"squared_error", e.squaredError},
                                 {"error_share", e.share},
                                 {"in_reference", e.inReference}});
            seed["partitions"] = parts;
        }
        perSeed.push_back(seed);
    }
    j["per_seed"] = perSeed;
    j["layers"] = layersJson(run, layerOrder, referenceErrors);
    if (auto sum = shareSum(run)) {
        j["partitions"] = partitionsJson(run, referenceErrors);
        j["partition_error_share_sum_mean"] = *sum;
        if (!run.partitionsOf.empty()) j["partitions_of"] = run.partitionsOf;
    }
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
    printPartitionRows(runs, referenceErrors);
    printEstimateRows(runs);
}

}  // namespace partita::eval
