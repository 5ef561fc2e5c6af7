#include "integrators/bdpt/bdpt_integrator.h"

#include "integrators/bdpt/bdpt_passes.h"
#include "integrators/sample_passes.h"

namespace partita {

RenderResult BdptAlgorithm::render(const RenderContext& ctx) {
    return renderSamplePasses(
        ctx,
        [this](const RenderContext& c, const TypeLayers& layers) {
            return std::make_unique<BdptPasses>(c, settings_, layers);
        },
        settings_);
}

BdptAlgorithm::BdptAlgorithm(BdptSettings settings) : settings_(settings) {}
BdptAlgorithm::~BdptAlgorithm() = default;

Shardable* BdptAlgorithm::shardable() {
    if (!shards_)
        shards_ = std::make_unique<SamplePassShards>(
            [settings = settings_](const RenderContext& ctx, const TypeLayers& layers) {
                return std::make_unique<BdptPasses>(ctx, settings, layers);
            },
            settings_);
    return shards_.get();
}

namespace {

const SettingsTable<BdptSettings>& bdptParameters() {
    static const SettingsTable<BdptSettings> table = [] {
        SettingsTable<BdptSettings> t;
        t.addAll(samplePassParameters());
        return t;
    }();
    return table;
}

}  // namespace

void registerBdpt() {
    AlgorithmRegistry::instance().add(algorithmEntry<BdptAlgorithm>(
        "bdpt",
        "bidirectional path tracer: every (s, t) strategy including light tracing, MIS "
        "(power heuristic); per-type layers",
        BudgetKind::SamplesPerPixel, bdptParameters(), /*orthographicCamera=*/true));
}

}  // namespace partita
