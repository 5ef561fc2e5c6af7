#include "integrators/partitioned/partitioned_integrator.h"

#include "mcmc/veach_mutations.h"
#include "partition/partitioned_pipeline.h"

namespace partita {

ChainRunner::MutationFactory VeachPartitionMutations::factory(
    const RenderContext& ctx, const std::vector<Partition>& partitions, std::span<const uint8_t>) {
    return [this, &ctx, partitions](uint32_t group) {
        return makeVeachMutations(ctx.scene, ctx.camera, ctx.settings.maxDepth,
                                  partitionMutationSettings(settings_, partitions[group]));
    };
}

PartitionedAlgorithm::PartitionedAlgorithm(PartitionedSettings settings)
    : settings_(std::move(settings)),
      mutations_(settings_.mutations),
      shards_(settings_, "partitioned", mutations_) {}

PartitionedAlgorithm::~PartitionedAlgorithm() = default;

RenderResult PartitionedAlgorithm::render(const RenderContext& ctx) {
    return renderPartitioned(ctx, settings_, "partitioned", mutations_);
}

void registerPartitioned() {
    AlgorithmRegistry::instance().add(algorithmEntry<PartitionedAlgorithm>(
        "partitioned",
        "path-space partitioning (paper Sec. 4): a pre-pass ranks the path types, the top K and "
        "their complement get their own MLT chains and normalising constants; one layer per "
        "partition",
        BudgetKind::MutationsPerPixel, partitionedParameters(), /*orthographicCamera=*/false));
}

}  // namespace partita
