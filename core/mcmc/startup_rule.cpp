#include "mcmc/startup_rule.h"

#include <algorithm>
#include <cmath>

namespace partita {

uint64_t StartupRule::bootstrapSamples(uint64_t requested, const RenderSettings& s) {
    if (requested > 0) return requested;
    if (s.budgetKind != BudgetKind::MutationsPerPixel) return kMaxSamples;
    const double mutations = s.budget * double(s.width) * double(s.height);
    const double samples = std::ceil(mutations / kSampleCost);
    return uint64_t(std::clamp(samples, double(kMinSamples), double(kMaxSamples)));
}

uint64_t StartupRule::burnIn(uint64_t burnIn, uint64_t mutations, const RenderSettings& s) {
    if (s.budgetKind != BudgetKind::MutationsPerPixel) return burnIn;
    return std::min(burnIn, uint64_t(double(mutations) * kBurnInShare));
}

}  // namespace partita
