#include "integrators/bdpt/bdpt_integrator.h"

#include "integrators/bdpt/bdpt_passes.h"
#include "integrators/sample_passes.h"

namespace partita {

RenderResult BdptAlgorithm::render(const RenderContext& ctx) {
    return renderSamplePasses(ctx, [this](const RenderContext& c, const TypeLayers& layers) {
        return std::make_unique<BdptPasses>(c, settings_, layers);
    });
}

BdptAlgorithm::BdptAlgorithm(BdptSettings settings) : settings_(settings) {}
BdptAlgorithm::~BdptAlgorithm() = default;

Shardable* BdptAlgorithm::shardable() {
    if (!shards_)
        shards_ = std::make_unique<SamplePassShards>(
            [settings = settings_](const RenderContext& ctx, const TypeLayers& layers) {
                return std::make_unique<BdptPasses>(ctx, settings, layers);
            });
    return shards_.get();
}

void registerBdpt() {
    AlgorithmRegistry::instance().add(
        {"bdpt",
         "bidirectional path tracer: every (s, t) strategy including light tracing, MIS "
         "(power heuristic); per-type layers",
         BudgetKind::SamplesPerPixel,
         [](const ParameterValues&) { return std::make_unique<BdptAlgorithm>(); },
         /*orthographicCamera=*/true, /*parameters=*/{}});
}

}  // namespace partita
