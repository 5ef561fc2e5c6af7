// Guided image sampling as an Algorithm ("guided", paper Sec. 5 on top of Sec. 4): the
// partitioned chains of `partitioned` (partition/partitioned_pipeline.h), with the lens
// perturbation replaced by the guided image perturbation (guide/guided_perturbation.h). After the
// pre-pass it builds the guides: the G-buffer (guide/gbuffer.h), each partition's pre-pass image
// (partition/partition_images.h) denoised with it (guide/denoise.h) and thresholded into V'
// (guide/image_guide.h, Eq. 17), and the offsets Delta (guide/offsets.h, Eq. 18) from the job's
// |Y'| and R.
#pragma once

#include <memory>

#include "algorithm.h"
#include "integrators/guided/guided_settings.h"
#include "partition/partitioned_pipeline.h"

namespace partita {

struct Guides;

/// guided's mutations: partitioned's with the guided image perturbation for the lens
/// perturbation. prepare() builds the guides (G-buffer, denoised pre-pass images, support
/// masks) and returns the masks; a shard rebuilds the G-buffer (deterministic: one ray per
/// pixel centre, 83 ms at 1280x720) rather than carrying its 37 MB in the plan.
class GuidedMutations : public PartitionMutations {
  public:
    explicit GuidedMutations(const GuidedSettings& settings) : settings_(settings) {}
    std::vector<uint8_t> prepare(const RenderContext& ctx, const PrepassResult& prepass,
                                 const std::vector<Partition>& partitions,
                                 RenderStats& stats) override;
    ChainRunner::MutationFactory factory(const RenderContext& ctx,
                                         const std::vector<Partition>& partitions,
                                         std::span<const uint8_t> prepared) override;
    /// settings.move: "guided" or "lens" alone, or both for the pilot to choose ("auto").
    std::vector<std::string> moves() const override;

  private:
    const GuidedSettings& settings_;
    std::shared_ptr<Guides> prepared_;  // prepare()'s guides, for this process's chains
};

class GuidedAlgorithm : public Algorithm {
  public:
    explicit GuidedAlgorithm(GuidedSettings settings = {});
    ~GuidedAlgorithm() override;
    RenderResult render(const RenderContext& ctx) override;
    Shardable* shardable() override { return &shards_; }

  private:
    GuidedSettings settings_;
    GuidedMutations mutations_;
    PartitionedShards shards_;
};

void registerGuided();

}  // namespace partita
