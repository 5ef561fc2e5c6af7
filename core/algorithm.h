// What the scheduler runs: an Algorithm renders a RenderScene under a budget, watching a cancel
// flag and reporting progress and previews through a RenderObserver. Algorithms register
// themselves by name (pt, bdpt, mlt, partitioned, guided), so front ends and the service only
// ever name them.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "image.h"
#include "render_settings.h"

namespace partita {

class RenderScene;
class Camera;
class ThreadPool;
class Shardable;

/// Thrown out of Algorithm::render when the cancel flag is raised.
struct RenderCancelled {};

/// Per-partition statistics of the MCMC algorithms (paper Sec. 4): type string, running
/// acceptance rate, normalising constant b_i, selection probability P(i) and the pre-pass's
/// gamma.
struct PartitionProgress {
    std::string type;
    double acceptance = 0, b = 0, p = 0, gamma = 0;
    std::string estimator;  // "chains" or "per-pixel" (issue #23 1); empty: chains
    /// A chains' partition's image-plane move where the algorithm chooses one per partition
    /// (guided: "guided" or "lens", PartitionMutations::moves); empty otherwise.
    std::string move;
};

/// One progress report. `done`/`total` are in `unit` (e.g. "samples", "mutations").
struct RenderProgress {
    std::string phase;  // "prepass", "render", ...
    double done = 0, total = 0;
    std::string unit;
    double ratePerSecond = 0;
    double etaSeconds = -1;  // < 0: unknown
    double elapsedSeconds = 0;
    std::vector<PartitionProgress> partitions;  // empty for algorithms without partitions
    /// Named statistics of the phase so far (mlt: "acceptance_<mutation>", "mutations"); empty
    /// when the algorithm reports none.
    std::map<std::string, double> values;
};

/// Named scalar statistics an algorithm reports (acceptance, b_i, ...), and named strings.
struct RenderStats {
    std::map<std::string, double> values;
    std::map<std::string, std::string> labels;
};

class RenderObserver {
  public:
    virtual ~RenderObserver() = default;
    virtual void onProgress(const RenderProgress&) {}
    /// A preview of the work so far, at most once per preview interval, and never for the final
    /// result (that is returned by render()). The image is the observer's to keep (an algorithm
    /// resolves a fresh one for each call and moves it in), so keeping it costs no copy.
    virtual void onPreview(LayeredImage /*image*/, const RenderStats&) {}
    /// Whether onPreview is worth calling at all: an observer that shows no previews says no,
    /// and algorithms then resolve none (a preview of a film with thousands of types costs
    /// about a fifth of a path-traced bathroom at one a second).
    virtual bool wantsPreviews() const { return true; }
    /// The seconds the observer's side spent delivering its last preview, on threads of its
    /// own (the daemon encodes each frame's layers as PNGs for its watchers): previews are
    /// spaced by it as by their own resolve (preview_schedule.h).
    virtual double previewDeliverySeconds() const { return 0; }
};

struct RenderContext {
    const RenderScene& scene;
    const Camera& camera;
    const RenderSettings& settings;
    ThreadPool& pool;
    const std::atomic<bool>& cancel;
    RenderObserver& observer;

    void throwIfCancelled() const {
        if (cancel.load(std::memory_order_relaxed)) throw RenderCancelled{};
    }
};

struct RenderResult {
    LayeredImage image;
    RenderStats stats;
};

class Algorithm {
  public:
    virtual ~Algorithm() = default;
    virtual RenderResult render(const RenderContext& ctx) = 0;
    /// How the algorithm runs as shards in several processes (shard/shardable.h); null when it
    /// cannot. Owned by the algorithm.
    virtual Shardable* shardable() { return nullptr; }
};

/// The registry of algorithms by name. Each entry declares its own parameters (beyond the
/// shared ones of render_settings.h) and makes the algorithm from a job's values of them.
class AlgorithmRegistry {
  public:
    /// The algorithm with its settings resolved from the job's values of its parameters (unset
    /// ones take the declared defaults). Throws std::invalid_argument naming a bad value.
    using Factory = std::function<std::unique_ptr<Algorithm>(const ParameterValues&)>;
    struct Entry {
        std::string name, description;
        /// Its budget unit: samples for pt/bdpt, mutations for the MCMC methods; every
        /// algorithm also takes a time budget (budgets()).
        BudgetKind nativeBudget;
        Factory factory;
        /// Whether it renders through an orthographic camera (the MCMC methods connect paths to
        /// a pinhole and need a perspective one).
        bool orthographicCamera = true;
        /// Its own parameters, declared next to its settings struct (params/settings_table.h).
        std::vector<ParameterSpec> parameters;

        std::vector<BudgetKind> budgets() const { return {nativeBudget, BudgetKind::Seconds}; }
    };

    static AlgorithmRegistry& instance();
    void add(Entry entry);
    const Entry* find(const std::string& name) const;
    std::vector<std::string> names() const;

  private:
    std::map<std::string, Entry> entries_;
};

/// The entry of algorithm A, whose constructor takes the settings S that `table` declares.
template <class A, class S>
AlgorithmRegistry::Entry algorithmEntry(std::string name, std::string description,
                                        BudgetKind nativeBudget, const SettingsTable<S>& table,
                                        bool orthographicCamera = true) {
    AlgorithmRegistry::Entry e;
    e.name = std::move(name);
    e.description = std::move(description);
    e.nativeBudget = nativeBudget;
    e.orthographicCamera = orthographicCamera;
    e.parameters = table.specs();
    e.factory = [&table](const ParameterValues& values) -> std::unique_ptr<Algorithm> {
        return std::make_unique<A>(table.resolve(values));
    };
    return e;
}

/// Registers every built-in algorithm; idempotent. Called by front ends at start-up (static
/// registration from a static library would be dropped by the linker).
void registerBuiltinAlgorithms();

}  // namespace partita
