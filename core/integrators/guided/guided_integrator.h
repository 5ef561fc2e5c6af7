// Guided image sampling as an Algorithm ("guided", paper Sec. 5 on top of Sec. 4): the
// partitioned chains of `partitioned` (partition/partitioned_pipeline.h), with the lens
// perturbation replaced by the guided image perturbation (guide/guided_perturbation.h). After the
// pre-pass it builds the guides: the G-buffer (guide/gbuffer.h), each partition's pre-pass image
// (partition/partition_images.h) denoised with it (guide/denoise.h) and thresholded into V'
// (guide/image_guide.h, Eq. 17), and the offsets Delta (guide/offsets.h, Eq. 18) from the job's
// |Y'| and R.
#pragma once

#include "algorithm.h"
#include "integrators/guided/guided_settings.h"

namespace partita {

class GuidedAlgorithm : public Algorithm {
  public:
    explicit GuidedAlgorithm(GuidedSettings settings = {}) : settings_(settings) {}
    RenderResult render(const RenderContext& ctx) override;

  private:
    GuidedSettings settings_;
};

void registerGuided();

}  // namespace partita
