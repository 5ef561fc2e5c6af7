#include "integrators/partitioned/partitioned_integrator.h"

#include "mcmc/veach_mutations.h"
#include "partition/partitioned_pipeline.h"

namespace partita {

RenderResult PartitionedAlgorithm::render(const RenderContext& ctx) {
    auto hook = [&](const PrepassResult&, const std::vector<Partition>& partitions,
                    RenderStats&) -> ChainRunner::MutationFactory {
        return [&, partitions](uint32_t group) {
            return makeVeachMutations(
                ctx.scene, ctx.camera, ctx.settings.maxDepth,
                partitionMutationSettings(settings_.mutations, partitions[group]));
        };
    };
    return renderPartitioned(ctx, settings_, "partitioned", hook);
}

void registerPartitioned() {
    AlgorithmRegistry::instance().add(
        {"partitioned",
         "path-space partitioning (paper Sec. 4): a pre-pass ranks the path types, the top K and "
         "their complement get their own MLT chains and normalising constants; one layer per "
         "partition",
         BudgetKind::MutationsPerPixel, [] { return std::make_unique<PartitionedAlgorithm>(); },
         /*orthographicCamera=*/false});
}

}  // namespace partita
