// finalizeRenderOptions lives apart from addRenderOptions: it needs the algorithm registry and
// so the whole core, which clients that only share the flags (the `partita` CLI) must not link.
#include "algorithm.h"
#include "frontend/render_options.h"

namespace partita {

std::string finalizeRenderOptions(RenderOptions& o) {
    registerBuiltinAlgorithms();
    const auto* entry = AlgorithmRegistry::instance().find(o.algorithm);
    if (!entry) {
        std::string known;
        for (const auto& n : AlgorithmRegistry::instance().names())
            known += (known.empty() ? "" : ", ") + n;
        return "unknown algorithm '" + o.algorithm + "' (available: " + known + ")";
    }
    RenderSettings& s = o.settings;
    if (o.spp) {
        s.budgetKind = BudgetKind::SamplesPerPixel;
        s.budget = *o.spp;
    } else if (o.mpp) {
        s.budgetKind = BudgetKind::MutationsPerPixel;
        s.budget = *o.mpp;
    } else if (o.seconds) {
        s.budgetKind = BudgetKind::Seconds;
        s.budget = *o.seconds;
    } else {
        s.budgetKind = entry->nativeBudget;
        s.budget = 16;
    }
    if (o.threads < 0 || o.threads > 4096) return "threads must be in 0..4096";
    return validateSettings(s);
}

}  // namespace partita
