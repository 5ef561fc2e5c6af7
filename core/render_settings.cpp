#include "render_settings.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace partita {

std::string validateSettings(const RenderSettings& s, const RenderLimits& limits) {
    std::ostringstream err;
    if (s.width < 1 || s.height < 1 || s.width > limits.maxWidth || s.height > limits.maxHeight)
        err << "resolution " << s.width << "x" << s.height << " is outside 1x1.." << limits.maxWidth
            << "x" << limits.maxHeight;
    else if (!std::isfinite(s.budget) || s.budget <= 0)
        err << "budget must be a positive number, got " << s.budget;
    else if (s.budgetKind == BudgetKind::Seconds && s.budget > limits.maxSeconds)
        err << "time budget " << s.budget << " s exceeds the limit of " << limits.maxSeconds
            << " s";
    else if (s.budgetKind != BudgetKind::Seconds && s.budget > limits.maxSamplesPerPixel)
        err << "budget " << s.budget << " per pixel exceeds the limit of "
            << limits.maxSamplesPerPixel;
    else if (s.budgetKind != BudgetKind::Seconds && s.budget != std::floor(s.budget))
        err << "samples/mutations per pixel must be a whole number, got " << s.budget;
    else if (s.maxDepth < 1 || s.maxDepth > limits.maxDepth)
        err << "max depth " << s.maxDepth << " is outside 1.." << limits.maxDepth;
    else if (s.partitions < 0 || s.partitions > 64)
        err << "K (partitions) " << s.partitions << " is outside 0..64";
    else if (s.prepass != "auto" && s.prepass != "pt" && s.prepass != "bdpt")
        err << "pre-pass '" << s.prepass << "' is not one of auto, pt, bdpt";
    else if (s.guideCandidates < 1 || s.guideCandidates > 4096)
        err << "|Y'| " << s.guideCandidates << " is outside 1..4096";
    else if (!std::isfinite(s.guideRadius) || s.guideRadius <= 0 || s.guideRadius > 4096)
        err << "radius R " << s.guideRadius << " is outside (0, 4096]";
    else if (!std::isfinite(s.guideEpsilon) || s.guideEpsilon <= 0 || s.guideEpsilon > 1)
        err << "epsilon " << s.guideEpsilon << " is outside (0, 1]";
    else if (s.bootstrapSamples > limits.maxBootstrapSamples)
        err << "bootstrap samples " << s.bootstrapSamples << " exceed the limit of "
            << limits.maxBootstrapSamples;
    else if (s.maxTypeLayers < 0 || s.maxTypeLayers > 1024)
        err << "max type layers " << s.maxTypeLayers << " is outside 0..1024";
    else if (!std::isfinite(s.previewIntervalSeconds) || s.previewIntervalSeconds < 0)
        err << "preview interval must be >= 0 seconds";
    else if (!s.environment.file.empty() && s.environment.hasColor)
        err << "give an environment file or an environment colour, not both";
    else if (!std::isfinite(s.environment.rotationDegrees) ||
             std::abs(s.environment.rotationDegrees) > 360000)
        err << "environment rotation must be a finite number of degrees";
    else if (s.environment.hasColor &&
             std::any_of(s.environment.color.begin(), s.environment.color.end(),
                         [](float c) { return !std::isfinite(c) || c < 0 || c > 1e6f; }))
        err << "environment colour components must be in [0, 1e6]";
    return err.str();
}

}  // namespace partita
