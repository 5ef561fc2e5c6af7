// Running a render in a test and summarising repeated renders with independent seeds.
#pragma once

#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include "algorithm.h"
#include "camera.h"
#include "render_scene.h"
#include "renderer.h"
#include "statistics.h"
#include "thread_pool.h"

namespace partita::test {

/// What a test needs to drive the core's parts (a chain runner, a shard plan) rather than a
/// whole render: `settings`, the scene's default camera for them, a pool of `threads`, and the
/// context over them all.
struct TestRenderContext {
    TestRenderContext(const RenderScene& scene, const RenderSettings& s, int threads = 2)
        : settings(s),
          camera(resolveCamera(scene.data(), ""), s.width, s.height),
          pool(threads),
          ctx{scene, camera, settings, pool, cancel, observer} {}

    RenderSettings settings;
    Camera camera;
    ThreadPool pool;
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    RenderContext ctx;
};

inline RenderResult renderWith(const RenderScene& scene, const std::string& algorithm,
                               const RenderSettings& settings, int threads = 2) {
    ThreadPool pool(threads);
    std::atomic<bool> cancel{false};
    RenderObserver observer;
    return runRender(scene, algorithm, settings, pool, cancel, observer);
}

}  // namespace partita::test
