#include "partition/prepass.h"

#include <algorithm>
#include <stdexcept>

#include "light.h"
#include "progress_reporter.h"
#include "render_scene.h"
#include "sample_waves.h"
#include "thread_pool.h"

namespace partita {

namespace {
constexpr uint64_t kBlock = 256;
}

StartupEstimator choosePrepassEstimator(const RenderScene& scene, const std::string& setting,
                                        std::string& why) {
    if (setting == "pt") {
        why = "pt: asked for";
        return StartupEstimator::PathTracer;
    }
    if (setting == "bdpt") {
        why = "bdpt: asked for";
        return StartupEstimator::Bidirectional;
    }
    if (setting != "auto")
        throw std::invalid_argument("pre-pass '" + setting + "' is not one of pt, bdpt, auto");
    for (const Light& light : scene.lights())
        if (isDeltaLight(light)) {
            why = "bdpt: the scene has a delta light, whose caustics a path tracer cannot sample";
            return StartupEstimator::Bidirectional;
        }
    why = "pt: the paper's pre-pass (no delta light in the scene)";
    return StartupEstimator::PathTracer;
}

PrepassResult runPrepass(const RenderContext& ctx, const BootstrapSampler& sampler,
                         uint64_t samples, uint64_t maxCandidateBytes, Deadline deadline) {
    ProgressReporter progress(ctx.observer, "prepass", "samples", double(samples));
    struct Block {
        std::map<PathType, double> gamma, sumB, sumSquaresB;
        std::vector<BootstrapCandidate> candidatesB;
        uint64_t rays = 0;
    };
    auto run = [&](uint64_t k, Block& block) {
        std::vector<BootstrapCandidate> scratch;
        std::vector<std::pair<PathType, double>> perType;  // this sample's C per type
        uint64_t first = k * kBlock, end = std::min(samples, first + kBlock);
        for (uint64_t i = first; i < end; ++i) {
            if ((i & 15) == 0) ctx.throwIfCancelled();
            scratch.clear();
            sampler.sample(i, scratch, block.rays);
            bool halfB = i % 2 == 1;
            if (!halfB) {
                for (const BootstrapCandidate& c : scratch) block.gamma[c.type] += c.weight;
                continue;
            }
            perType.clear();
            for (const BootstrapCandidate& c : scratch) {
                auto same = [&](const auto& e) { return e.first == c.type; };
                auto it = std::find_if(perType.begin(), perType.end(), same);
                if (it != perType.end())
                    it->second += c.weight;
                else
                    perType.push_back({c.type, c.weight});
            }
            for (const auto& [type, c] : perType) {
                block.sumB[type] += c;
                block.sumSquaresB[type] += c * c;
            }
            block.candidatesB.insert(block.candidatesB.end(), scratch.begin(), scratch.end());
        }
        progress.advance(double(end - first));
    };
    PrepassResult r;
    size_t maxCandidates = size_t(maxCandidateBytes / sizeof(BootstrapCandidate));
    // Room for the records the samples are expected to leave (kCandidatesPerSample), at most the
    // budget: reserved, so that the list does not double past it (untouched, costs nothing).
    r.candidatesB.reserve(size_t(
        std::min<double>(double(maxCandidates), double(samples / 2) * kCandidatesPerSample)));
    auto merge = [&](Block& block) {  // in block order: the same sums for any thread count
        for (const auto& [type, c] : block.gamma) r.gamma[type] += c;
        for (const auto& [type, c] : block.sumB) r.sumB[type] += c;
        for (const auto& [type, c2] : block.sumSquaresB) r.sumSquaresB[type] += c2;
        r.rays += block.rays;
        size_t room = maxCandidates - std::min(maxCandidates, r.candidatesB.size());
        if (block.candidatesB.size() > room) r.candidatesTruncated = true;
        r.candidatesB.insert(
            r.candidatesB.end(), block.candidatesB.begin(),
            block.candidatesB.begin() + long(std::min(room, block.candidatesB.size())));
    };
    uint64_t blocks = (samples + kBlock - 1) / kBlock;
    uint64_t ran =
        runInWaves<Block>(ctx.pool, blocks, run, merge, [&] { return Clock::now() >= deadline; });
    progress.flush();
    uint64_t used = std::min(samples, ran * kBlock);
    r.samplesB = used / 2;
    r.samplesA = used - r.samplesB;
    return r;
}

}  // namespace partita
