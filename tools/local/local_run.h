// What partita-local's commands (main.cpp, shard_commands.cpp) share: the progress bar as a
// render observer, the check that an output can be written before any work, and loading a
// scene file with the job's environment.
#pragma once

#include <string>

#include "algorithm.h"
#include "frontend/progress_bar.h"
#include "render_scene.h"
#include "render_settings.h"

namespace partita {

/// Forwards progress to a progress bar, unless quiet.
class BarObserver : public RenderObserver {
  public:
    BarObserver(ProgressBar& bar, bool quiet) : bar_(bar), quiet_(quiet) {}
    void onProgress(const RenderProgress& p) override {
        if (!quiet_) bar_.update(p);
    }
    /// A local render shows its progress, never a preview: none is resolved.
    bool wantsPreviews() const override { return false; }

  private:
    ProgressBar& bar_;
    bool quiet_;
};

/// The glTF file at `path` (its warnings logged) with `environment` attached, ready to render.
RenderScene loadLocalScene(const std::string& path, const EnvironmentSettings& environment);

}  // namespace partita
