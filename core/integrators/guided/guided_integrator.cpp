#include "integrators/guided/guided_integrator.h"

#include <memory>
#include <stdexcept>
#include <string>

#include "clock.h"
#include "guide/denoise.h"
#include "guide/gbuffer.h"
#include "guide/guided_perturbation.h"
#include "guide/image_guide.h"
#include "guide/offsets.h"
#include "partition/partition_images.h"
#include "progress_reporter.h"
#include "thread_pool.h"

namespace partita {

/// What the guided perturbations of every chain read: built once after the pre-pass, alive as
/// long as the chains' mutation factory.
struct Guides {
    GBuffer gbuffer;
    SupportMasks masks;  // per partition, D_i > epsilon (relative to its mean)
    std::vector<ImageGuide> perPartition;
    std::vector<PixelOffset> delta;

    /// perPartition and delta, from gbuffer and masks.
    void link(const GuidedSettings& settings, size_t partitions) {
        perPartition.clear();
        for (size_t g = 0; g < partitions; ++g) perPartition.emplace_back(gbuffer, masks, g);
        delta = guideOffsets(settings.y, settings.radius);
    }
};

namespace {

std::shared_ptr<Guides> buildGuides(const RenderContext& ctx, const PrepassResult& prepass,
                                    const std::vector<Partition>& partitions,
                                    const GuidedSettings& settings, RenderStats& stats) {
    const RenderSettings& rs = ctx.settings;
    auto start = Clock::now();
    // Its own phase, after "prepass" (the job stays in PREPASS): G-buffer, denoise, thresholds.
    ProgressReporter progress(ctx.observer, "guides", "steps", 3);
    auto guides = std::make_shared<Guides>();
    guides->gbuffer = buildGBuffer(ctx);
    progress.advance(1);
    double gbufferSeconds = secondsSince(start);
    std::vector<std::vector<float>> images =
        partitionPrepassImages(prepass, partitions, rs.width, rs.height);
    ctx.throwIfCancelled();
    std::vector<std::vector<float>> denoised =
        denoisePartitions(guides->gbuffer, images, settings.denoise, &ctx.pool);
    progress.advance(1);
    double denoiseSeconds = secondsSince(start) - gbufferSeconds;
    for (std::vector<float>& d : denoised) d = relativeToMean(d);
    guides->masks = SupportMasks(denoised, rs.width, rs.height, settings.epsilon);
    guides->link(settings, partitions.size());
    for (size_t g = 0; g < partitions.size(); ++g)
        stats.values["partition_" + std::to_string(g) + "_guide_support"] =
            guides->perPartition[g].supportFraction();
    size_t guideBytes = guides->gbuffer.bytes() + guides->masks.bytes();
    progress.advance(1);
    progress.flush();
    stats.values["guide_candidates"] = double(settings.y);
    stats.values["guide_radius"] = double(settings.radius);
    stats.values["guide_epsilon"] = double(settings.epsilon);
    stats.values["gbuffer_seconds"] = gbufferSeconds;
    stats.values["denoise_seconds"] = denoiseSeconds;
    stats.values["guide_seconds"] = secondsSince(start);
    stats.values["guide_bytes"] = double(guideBytes);
    return guides;
}

}  // namespace

std::vector<uint8_t> GuidedMutations::prepare(const RenderContext& ctx,
                                              const PrepassResult& prepass,
                                              const std::vector<Partition>& partitions,
                                              RenderStats& stats) {
    prepared_ = buildGuides(ctx, prepass, partitions, settings_, stats);
    return prepared_->masks.serialize();
}

ChainRunner::MutationFactory GuidedMutations::factory(const RenderContext& ctx,
                                                      const std::vector<Partition>& partitions,
                                                      std::span<const uint8_t> prepared) {
    // prepare()'s guides serve every factory of this job (the pilot's, one per move, and the
    // chains'): an algorithm object renders one job (algorithm.h).
    std::shared_ptr<Guides> guides = prepared_;
    if (!guides) {  // a shard: the masks from the plan, the G-buffer traced again
        guides = std::make_shared<Guides>();
        guides->masks = SupportMasks::deserialize(prepared);
        if (guides->masks.partitions() != partitions.size() ||
            guides->masks.width() != ctx.settings.width ||
            guides->masks.height() != ctx.settings.height)
            throw std::invalid_argument("guided plan: the support masks do not fit the job");
        guides->gbuffer = buildGBuffer(ctx);
        guides->link(settings_, partitions.size());
        prepared_ = guides;
    }
    // Each partition's move, checked once: the lens perturbation is partitioned's mutations.
    const std::vector<std::string> moves = this->moves();
    std::vector<bool> lens;
    for (const Partition& p : partitions) {
        if (p.move >= moves.size())
            throw std::invalid_argument("guided: a partition's move is not one of " +
                                        std::to_string(moves.size()));
        lens.push_back(moves[p.move] == "lens");
    }
    return [this, &ctx, guides, partitions, lens](uint32_t group) {
        VeachMutationSettings m = partitionMutationSettings(settings_.mutations, partitions[group]);
        if (lens[group]) return makeVeachMutations(ctx.scene, ctx.camera, ctx.settings.maxDepth, m);
        auto guided = std::make_unique<GuidedPerturbation>(
            ctx.scene, ctx.camera, guides->perPartition[group], guides->delta,
            lensPixelRange(ctx.camera, m), settings_.throughSpecular);
        return makeVeachMutations(ctx.scene, ctx.camera, ctx.settings.maxDepth, m,
                                  std::move(guided));
    };
}

std::vector<std::string> GuidedMutations::moves() const {
    if (settings_.move == "auto") return {"guided", "lens"};
    return {settings_.move};
}

GuidedAlgorithm::GuidedAlgorithm(GuidedSettings settings)
    : settings_(std::move(settings)),
      mutations_(settings_),
      shards_(settings_, "guided", mutations_) {}

GuidedAlgorithm::~GuidedAlgorithm() = default;

RenderResult GuidedAlgorithm::render(const RenderContext& ctx) {
    return renderPartitioned(ctx, settings_, "guided", mutations_);
}

void registerGuided() {
    AlgorithmRegistry::instance().add(algorithmEntry<GuidedAlgorithm>(
        "guided",
        "guided image sampling (paper Sec. 5): the partitioned chains with the lens "
        "perturbation replaced by a move on the image plane drawn from |Y'| candidate pixels "
        "within R in proportion to a G-buffer estimate S' and a denoised pre-pass visibility "
        "V'; one layer per partition",
        BudgetKind::MutationsPerPixel, guidedParameters(), /*orthographicCamera=*/false));
}

}  // namespace partita
