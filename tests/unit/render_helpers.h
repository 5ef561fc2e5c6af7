// Running a render in a test and summarising repeated renders with independent seeds.
#pragma once

#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "algorithm.h"
#include "render_scene.h"
#include "renderer.h"
#include "statistics.h"
#include "thread_pool.h"

namespace partita::test {

inline RenderResult renderWith(const RenderScene& scene, const std::string& algorithm,
                               const RenderSettings& settings, int threads = 2) {
    ThreadPool pool(threads);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    return runRender(scene, algorithm, settings, pool, cancel, observer);
}

}  // namespace partita::test
