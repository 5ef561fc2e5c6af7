// `partita-eval reference`: a reference image with every per-type layer, rendered as two
// independent halves of the budget (their mean is the reference, their difference its own
// error), cached under a key of the scene's bytes, the algorithm and the settings.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "frontend/render_options.h"

namespace partita::eval {

struct ReferenceOptions {
    std::string scene;
    std::string out;       // a copy of the reference here ("" = only in the cache)
    std::string cacheDir;  // "" = defaultReferenceCache()
    bool noCache = false;  // neither read nor write the cache (then --out is required)
    bool force = false;    // render even when cached, and replace the cached file
    bool quiet = false;
    RenderOptions render;  // algorithm "bdpt" and 1024 type layers unless set
};

/// $PARTITA_REFERENCE_CACHE, else "references" in the build tree of this executable
/// (build-bench/references for build-bench/bench/partita-eval).
std::string defaultReferenceCache();

/// Finds or renders the reference, prints what it did and the reference's own error, and
/// returns the figures as JSON (path, key, cached, seconds, error per layer).
nlohmann::json runReference(ReferenceOptions options);

}  // namespace partita::eval
