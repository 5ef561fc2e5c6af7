// The settings of `guided` with their defaults (paper Sec. 5; DESIGN.md), and the parameters a
// job sets them with (guidedParameters(): the pipeline's k, prepass, bootstrap, chains; y,
// radius, epsilon).
#pragma once

#include <string>

#include "guide/denoise.h"
#include "mcmc/veach_mutations.h"
#include "params/settings_table.h"
#include "partition/pipeline_settings.h"

namespace partita {

struct GuidedSettings : PartitionPipelineSettings {
    // |Y'|, R and epsilon: chosen with the |Y'| x R study and the epsilon sweep of
    // docs/guided-sweep.md, "guided: the |Y'| x R study (issue #13 item 6)" (cornell-glass and
    // bathroom, 32 mpp, RMSE ratios paired by seed). |Y'| = 128, the paper's: 32 and 512 tie
    // with it within about two standard errors, 8 loses 1..47% and shows structured noise.
    // R = 20: at 128x96 (12 seeds) R = 5..40 tie within 1.5% and R = 2 loses 5..12%; at 256x192
    // (4 seeds) R = 5 loses 2..4%, R = 20 ties with 10 on cornell-glass and beats it on bathroom
    // (0.92x): the good range moves up with the image, so much wider images may want a larger
    // R. epsilon (relative to D_i's mean, image_guide.h): 0.001..0.1 tie within 0.5% on
    // cornell-glass (3% on bathroom, within its noise); 0.01 is the middle of that flat range.
    int y = 128;            // |Y'|: candidate pixels per step (Sec. 5.1)
    float radius = 20;      // R: the candidates' disk, pixels (Eq. 18)
    float epsilon = 0.01f;  // V' where the denoised partition image is below it (Eq. 17)
    /// Veach's mutations as in `partitioned`, the guided image perturbation in the lens
    /// perturbation's place (with its weight).
    VeachMutationSettings mutations;
    /// The per-partition denoiser of the pre-pass images that V' thresholds (Eq. 17).
    DenoiseSettings denoise;
    /// Each partition's image-plane move: "guided" (the paper's, Sec. 5.1), "lens" (the lens
    /// perturbation, as partitioned's chains) or "auto": the chains' pilot runs both and each
    /// partition keeps the one of less measured error per cost (per mutation for a mutation
    /// budget, per second for a time budget; issue #23 item 6). Without a chains' pilot
    /// (estimators=chains with allocation=p, the paper's method) auto is "guided".
    std::string move = "auto";
    /// The guided move also for paths whose camera ray meets specular surfaces before their
    /// first non-specular vertex (E S+ D ..., the paper's); false: the lens perturbation for
    /// those (guided_perturbation.h).
    bool throughSpecular = false;
};

const SettingsTable<GuidedSettings>& guidedParameters();

}  // namespace partita
