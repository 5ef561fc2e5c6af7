#include "integrators/layer_survey.h"

#include <algorithm>
#include <cmath>

#include "camera.h"
#include "progress_reporter.h"
#include "type_layer_rule.h"

namespace partita {

namespace {

constexpr double kSurveyShare = 1.0 / 16;  // of an spp budget's samples
constexpr double kMinSurveySamples = 4096, kMaxSurveySamples = 65536;

}  // namespace

void surveySize(int width, int height, int& surveyWidth, int& surveyHeight) {
    const double pixels = double(width) * double(height);
    const double f = pixels > kSurveyPixels ? std::sqrt(kSurveyPixels / pixels) : 1.0;
    surveyWidth = std::max(1, int(std::floor(double(width) * f)));
    surveyHeight = std::max(1, int(std::floor(double(height) * f)));
}

uint64_t surveySamplesPerPixel(const RenderSettings& s) {
    double samples = kMaxSurveySamples;
    if (s.budgetKind == BudgetKind::SamplesPerPixel)
        samples = std::clamp(double(s.width) * double(s.height) * s.budget * kSurveyShare,
                             kMinSurveySamples, kMaxSurveySamples);
    int w = 0, h = 0;
    surveySize(s.width, s.height, w, h);
    return std::max<uint64_t>(1, uint64_t(std::ceil(samples / (double(w) * double(h)))));
}

TypeLayers surveyTypeLayers(const RenderContext& ctx, const SamplePassFactory& factory) {
    if (!needsTypeWeights(ctx.settings)) return chooseTypeLayers(ctx.settings, {});
    RenderSettings settings = ctx.settings;
    surveySize(ctx.settings.width, ctx.settings.height, settings.width, settings.height);
    settings.seed = ctx.settings.seed + kSurveySeedOffset;
    settings.previewIntervalSeconds = 0;
    const Camera camera = ctx.camera.resized(settings.width, settings.height);
    const RenderContext survey{ctx.scene, camera, settings, ctx.pool, ctx.cancel, ctx.observer};

    const uint64_t spp = surveySamplesPerPixel(ctx.settings);
    std::unique_ptr<SamplePassRenderer> renderer = factory(survey, TypeLayers::every());
    ProgressReporter progress(ctx.observer, "layers", "samples",
                              double(settings.width) * settings.height * double(spp));
    const uint64_t passSpp = std::max<uint64_t>(1, renderer->maxPassSamples());
    for (uint64_t first = 0; first < spp; first += passSpp) {
        ctx.throwIfCancelled();
        renderer->renderPass({first, std::min(spp, first + passSpp)}, progress);
    }
    progress.flush();
    return chooseTypeLayers(ctx.settings, renderer->film().typeLuminance(&ctx.pool));
}

}  // namespace partita
