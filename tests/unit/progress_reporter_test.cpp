// ProgressReporter: phase start, rate and ETA, named values (setValues) in the next report; and
// mlt's reports: the phases "bootstrap" (samples) and "render" (mutations), the latter with the
// running acceptance per mutation type, ending with the final statistics' acceptance;
// setPartitions; and partitioned's reports: "prepass" then "render" with one PartitionProgress
// per partition (type, P(i), b_i, gamma, running acceptance) equal to the final statistics.
#include <gtest/gtest.h>

#include <mutex>
#include <thread>

#include "gltf/gltf_loader.h"
#include "progress_reporter.h"
#include "render_helpers.h"

namespace partita {
namespace {

struct Recorder : RenderObserver {
    std::mutex mutex;
    std::vector<RenderProgress> reports;
    void onProgress(const RenderProgress& p) override {
        std::lock_guard lock(mutex);
        reports.push_back(p);
    }
};

TEST(ProgressReporter, ValuesGoOutWithTheNextReportAndStay) {
    Recorder r;
    ProgressReporter progress(r, "render", "mutations", 100, 0, /*minInterval=*/3600);
    ASSERT_EQ(r.reports.size(), 1u) << "the phase's start";
    EXPECT_TRUE(r.reports[0].values.empty());
    EXPECT_EQ(r.reports[0].done, 0);

    progress.setValues({{"acceptance_lens", 0.5}, {"mutations", 40}});
    EXPECT_EQ(r.reports.size(), 1u) << "setValues reports nothing by itself";
    progress.advance(40);
    EXPECT_EQ(r.reports.size(), 1u) << "within the interval";
    progress.flush();
    ASSERT_EQ(r.reports.size(), 2u);
    EXPECT_EQ(r.reports[1].done, 40);
    EXPECT_EQ(r.reports[1].values,
              (std::map<std::string, double>{{"acceptance_lens", 0.5}, {"mutations", 40}}));
    progress.advance(60);
    progress.flush();
    EXPECT_EQ(r.reports.back().values.at("acceptance_lens"), 0.5) << "kept until replaced";
    progress.setValues({{"mutations", 100}});
    progress.flush();
    EXPECT_EQ(r.reports.back().values, (std::map<std::string, double>{{"mutations", 100}}));
    EXPECT_EQ(r.reports.back().total, 100);
    EXPECT_EQ(r.reports.back().etaSeconds, 0);
}

TEST(ProgressReporter, SetValuesAndAdvanceFromManyThreads) {
    Recorder r;
    ProgressReporter progress(r, "render", "mutations", 4000, 0, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int i = 0; i < 1000; ++i) {
                progress.setValues({{"thread", double(t)}, {"i", double(i)}});
                progress.advance(1);
            }
        });
    for (auto& t : threads) t.join();
    progress.flush();
    EXPECT_EQ(r.reports.back().done, 4000);
    EXPECT_EQ(r.reports.back().values.size(), 2u);
    EXPECT_EQ(r.reports.back().values.at("i"), 999);
}

TEST(ProgressReporter, MltReportsBootstrapThenMutationsWithAcceptance) {
    RenderScene scene(loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell/cornell.gltf"));
    RenderSettings s;
    s.width = 16;
    s.height = 12;
    s.budgetKind = BudgetKind::MutationsPerPixel;
    s.budget = 4;
    s.previewIntervalSeconds = 0;
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    Recorder r;
    RenderResult result = runRender(scene, "mlt", s, pool, cancel, r);

    ASSERT_GE(r.reports.size(), 3u);
    EXPECT_EQ(r.reports.front().phase, "bootstrap");
    EXPECT_EQ(r.reports.front().unit, "samples");
    const RenderProgress& last = r.reports.back();
    EXPECT_EQ(last.phase, "render");
    EXPECT_EQ(last.unit, "mutations");
    EXPECT_EQ(last.done, 16 * 12 * 4);
    EXPECT_EQ(last.total, 16 * 12 * 4);
    EXPECT_GT(last.ratePerSecond, 0);
    EXPECT_EQ(last.etaSeconds, 0);
    bool renderStarted = false;
    for (const RenderProgress& p : r.reports) {
        if (p.phase == "render") renderStarted = true;
        EXPECT_EQ(p.phase, renderStarted ? "render" : "bootstrap");
        if (p.phase == "bootstrap") {
            EXPECT_TRUE(p.values.empty());
        }
    }
    EXPECT_EQ(last.values.at("mutations"), 16 * 12 * 4);
    // Every mutation proposed has its running acceptance, the final statistics' value.
    size_t acceptances = 0;
    for (const char* name : {"bidirectional", "lens", "caustic", "multi_chain", "independence"}) {
        double proposed = result.stats.values.at(std::string("proposed_") + name);
        auto it = last.values.find(std::string("acceptance_") + name);
        ASSERT_EQ(it != last.values.end(), proposed > 0) << name;
        if (it == last.values.end()) continue;
        ++acceptances;
        EXPECT_EQ(it->second, result.stats.values.at(std::string("acceptance_") + name)) << name;
    }
    EXPECT_GE(acceptances, 3u)
        << "cornell: at least the bidirectional, lens and independence mutations";
    // And the render's own error estimate (mcmc/chain_error_monitor.h), the final one's.
    ASSERT_TRUE(last.values.count("error_estimate"));
    EXPECT_GT(last.values.at("error_estimate"), 0.0);
    EXPECT_EQ(last.values.size(), acceptances + 2);
}

TEST(ProgressReporter, PartitionsGoOutWithTheNextReportAndStay) {
    Recorder r;
    ProgressReporter progress(r, "render", "mutations", 100, 0, /*minInterval=*/3600);
    EXPECT_TRUE(r.reports.front().partitions.empty());
    progress.setPartitions({{"LDE", 0.5, 2.0, 0.75, 1.5, "chains", ""},
                            {"complement", 0.25, 1.0, 0.25, 0.5, "chains", ""}});
    progress.advance(10);  // held back by the interval
    progress.flush();
    ASSERT_EQ(r.reports.back().partitions.size(), 2u);
    EXPECT_EQ(r.reports.back().partitions[0].type, "LDE");
    EXPECT_EQ(r.reports.back().partitions[0].p, 0.75);
    EXPECT_EQ(r.reports.back().partitions[0].gamma, 1.5);
    EXPECT_EQ(r.reports.back().partitions[1].type, "complement");
    progress.flush();
    EXPECT_EQ(r.reports.back().partitions.size(), 2u) << "they stay until replaced";
}

/// A 16x12 partitioned render of cornell-glass at 8 mpp (K = 3) with `estimators`, its
/// reports into `r`.
RenderResult partitionedWithReports(const std::string& estimators, Recorder& r) {
    RenderScene scene(
        loadGltfFile(std::string(PARTITA_SCENES_DIR) + "/cornell-glass/cornell-glass.gltf"));
    RenderSettings s;
    s.width = 16;
    s.height = 12;
    s.budgetKind = BudgetKind::MutationsPerPixel;
    s.budget = 8;
    s.parameters.set("k", 3).set("bootstrap", 4000).set("estimators", estimators);
    s.previewIntervalSeconds = 0;
    ThreadPool pool(2);
    std::atomic<bool> cancel{false};
    return runRender(scene, "partitioned", s, pool, cancel, r);
}

TEST(ProgressReporter, PartitionedReportsPrepassThenPartitions) {
    Recorder r;
    RenderResult result = partitionedWithReports("chains", r);

    ASSERT_GE(r.reports.size(), 3u);
    EXPECT_EQ(r.reports.front().phase, "prepass");
    EXPECT_EQ(r.reports.front().unit, "samples");
    for (const RenderProgress& p : r.reports)
        if (p.phase == "prepass") {
            EXPECT_TRUE(p.partitions.empty());
        }
    const RenderProgress& last = r.reports.back();
    EXPECT_EQ(last.phase, "render");
    int k = int(result.stats.values.at("partitions"));
    ASSERT_GE(k, 2);
    ASSERT_EQ(last.partitions.size(), size_t(k));
    double sumP = 0;
    for (int g = 0; g < k; ++g) {
        std::string key = "partition_" + std::to_string(g) + "_";
        const PartitionProgress& pp = last.partitions[size_t(g)];
        EXPECT_EQ(pp.type, result.stats.labels.at(key + "type"));
        EXPECT_EQ(pp.p, result.stats.values.at(key + "p"));
        EXPECT_EQ(pp.b, result.stats.values.at(key + "b"));
        EXPECT_EQ(pp.gamma, result.stats.values.at(key + "gamma"));
        EXPECT_EQ(pp.acceptance, result.stats.values.at(key + "acceptance"));
        EXPECT_GT(pp.b, 0);
        sumP += pp.p;
    }
    EXPECT_NEAR(sumP, 1.0, 1e-9);
}

TEST(ProgressReporter, PerPixelPartitionsReportTheirTableAndEveryPhase) {
    // Every partition per pixel: no chains' phase, yet the render phase carries the partition
    // table (their estimator "per-pixel"), after the pre-pass and the pilot.
    Recorder r;
    RenderResult result = partitionedWithReports("per-pixel", r);
    std::vector<std::string> phases;
    for (const RenderProgress& p : r.reports)
        if (phases.empty() || phases.back() != p.phase) phases.push_back(p.phase);
    EXPECT_EQ(phases, (std::vector<std::string>{"prepass", "pilot", "render"}));
    const RenderProgress& last = r.reports.back();
    ASSERT_EQ(last.partitions.size(), size_t(result.stats.values.at("partitions")));
    for (size_t g = 0; g < last.partitions.size(); ++g) {
        EXPECT_EQ(last.partitions[g].estimator, "per-pixel");
        EXPECT_EQ(last.partitions[g].type,
                  result.stats.labels.at("partition_" + std::to_string(g) + "_type"));
    }
}

}  // namespace
}  // namespace partita
