// The short first pass that chooses pt's and bdpt's type layers (issue #24, type_layer_rule.h).
//
// Rule: the integrator itself renders a downscaled copy of the image (the same view and image
// plane, at most kSurveyPixels pixels, aspect ratio kept) into a film that keeps every type, with
// sample streams of its own (seed + kSurveySeedOffset). Its per-type luminance totals are the
// weights the layers are chosen by. Samples: a sixteenth of an spp budget's, within [4096,
// 65536] (65536 under a time budget), rounded up to whole samples per survey pixel: at most
// ~6% of an spp render's work, and a fraction of a second. A function of the settings alone, so
// the layers are the same for any thread count, and the shard plan carries them to every shard.
#pragma once

#include "algorithm.h"
#include "integrators/sample_passes.h"
#include "type_layers.h"

namespace partita {

inline constexpr int kSurveyPixels = 16384;
inline constexpr uint64_t kSurveySeedOffset = 0x5355525645590000ull;  // "SURVEY"

/// The survey's raster: the image when it has at most kSurveyPixels pixels, else scaled down.
void surveySize(int width, int height, int& surveyWidth, int& surveyHeight);

/// The survey's samples per survey pixel for `settings` (see the rule above).
uint64_t surveySamplesPerPixel(const RenderSettings& settings);

/// The type layers of a pt/bdpt render with ctx's settings (type_layer_rule.h); runs the survey
/// only when the rule needs weights. Reports progress as phase "layers"; cancellable.
TypeLayers surveyTypeLayers(const RenderContext& ctx, const SamplePassFactory& factory);

}  // namespace partita
