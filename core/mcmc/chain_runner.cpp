#include "mcmc/chain_runner.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <stdexcept>

#include "camera.h"
#include "mcmc/startup_rule.h"
#include "path/path.h"
#include "progress_reporter.h"
#include "tent_filter.h"
#include "thread_pool.h"

namespace partita {

struct ChainRunner::Chain {
    Chain(MutationSet set, PathRestriction restriction, MarkovPath start, Rng rng,
          const PlannedChain& planned)
        : mutations(std::move(set)),
          markov(mutations.weighted, std::move(restriction), std::move(start), rng),
          plan(planned) {}

    MutationSet mutations;
    MarkovChain markov;
    const PlannedChain& plan;
    uint64_t done = 0;
    uint64_t burnInDone = 0;     // burn-in steps run
    uint64_t lastMove = 0;       // 1 + the index of its last mutation that moved; 0: none yet
    PathType startType;          // its path's type when its counted mutations began
    bool leftStartType = false;  // its path's type has differed from startType since
    bool oddHalf = false;        // every other chain of its group in plan order (halvesError)
    std::vector<Film*> films;    // where its splats go (see FilmLayout)
};

ChainRunner::ChainRunner(const RenderContext& ctx, const ChainPlan& plan,
                         const MutationFactory& mutations, const RestrictionFactory& restrictions,
                         uint64_t roundMutations, FilmLayout layout)
    : ctx_(ctx),
      plan_(plan),
      roundMutations_(std::max<uint64_t>(1, roundMutations)),
      layout_(layout) {
    int w = ctx.settings.width, h = ctx.settings.height;
    if (layout == FilmLayout::AllAndHalf && plan.groups.size() != 2)
        throw std::invalid_argument("chain plan: the all-and-half layout needs two groups");
    // PerGroupWithHalves (partitioned's): a group without chains (a partition estimated per
    // pixel) gets empty films, not two dense ones it would never fill (at 1920x1080, 100 MB a
    // partition).
    std::vector<bool> hasChains(plan.groups.size(), false);
    for (const PlannedChain& c : plan.chains) hasChains.at(c.group) = true;
    auto filmSize = [&](size_t g) {
        return layout == FilmLayout::PerGroupWithHalves && !hasChains[g] ? std::pair{0, 0}
                                                                         : std::pair{w, h};
    };
    for (size_t g = 0; g < plan.groups.size(); ++g) {
        const bool combinedOnly = layout == FilmLayout::AllAndHalf && g == 1;
        const auto [fw, fh] = filmSize(g);
        films_.emplace_back(fw, fh, combinedOnly ? TypeLayers::of({}) : plan.layers);
    }
    if (layout == FilmLayout::PerGroupWithHalves)
        for (size_t g = 0; g < plan.groups.size(); ++g) {
            const auto [fw, fh] = filmSize(g);
            films_.emplace_back(fw, fh, TypeLayers::of({}));
        }
    std::vector<uint64_t> chainsOfGroup(plan.groups.size(), 0);
    for (const PlannedChain& c : plan.chains) {
        MarkovPath start;
        start.vertices = deserializePath(ctx.scene, ctx.camera, c.start);
        if (!evaluatePath(ctx.scene, ctx.camera, start))
            throw std::invalid_argument("chain plan: a chain's start carries nothing");
        PathRestriction restriction = restrictions ? restrictions(c.group) : PathRestriction{};
        chains_.push_back(std::make_unique<Chain>(mutations(c.group), std::move(restriction),
                                                  std::move(start), Rng(plan.seed, c.stream), c));
        chains_.back()->oddHalf = (chainsOfGroup.at(c.group)++ % 2) == 1;
        chains_.back()->films = filmsOf(c.group, chains_.back()->oddHalf);
    }
}

ChainRunner::~ChainRunner() = default;

void ChainRunner::run(ProgressReporter& progress, double seconds,
                      const std::function<void(double)>& afterRound) {
    using Clock = std::chrono::steady_clock;
    auto start = Clock::now();
    // A time budget is not reproducible anyway, so its rounds shrink to a fraction of a second
    // (to stop close to the budget); a mutation budget keeps the fixed rounds of the plan.
    uint64_t roundLength = seconds > 0 ? std::min<uint64_t>(64, roundMutations_) : roundMutations_;
    burnIn(seconds);
    for (;;) {
        bool remaining = false;
        for (const auto& c : chains_) remaining |= c->done < c->plan.mutations;
        if (!remaining) break;
        auto roundStart = Clock::now();
        runRound(roundLength, progress);
        auto now = Clock::now();
        double elapsed = std::chrono::duration<double>(now - start).count();
        publishProgressValues(progress);
        if (afterRound) afterRound(elapsed);
        if (stopRequested_) break;
        if (seconds > 0 && elapsed >= seconds) break;
        if (seconds > 0) {
            double roundSeconds = std::chrono::duration<double>(now - roundStart).count();
            double perMutation = roundSeconds / double(roundLength);
            double target = std::min(0.25, std::max(0.0, seconds - elapsed));
            roundLength = uint64_t(
                std::clamp(target / std::max(perMutation, 1e-12), 1.0, double(roundMutations_)));
        }
    }
}

void ChainRunner::burnIn(double seconds) {
    using Clock = std::chrono::steady_clock;
    const auto deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(
                           std::chrono::duration<double>(seconds * StartupRule::kBurnInShare));
    ctx_.pool.parallelFor(chains_.size(), [&](size_t k) {
        Chain& c = *chains_[k];
        auto none = [](Vec2f, PathType, Rgb) {};
        for (uint64_t i = 0; i < c.plan.burnIn; ++i) {
            if ((i & 63) == 0) {
                ctx_.throwIfCancelled();
                if (seconds > 0 && Clock::now() >= deadline) break;
            }
            c.markov.step(none);
            ++c.burnInDone;
        }
    });
}

uint64_t ChainRunner::burnInSteps() const {
    uint64_t n = 0;
    for (const auto& c : chains_) n += c->burnInDone;
    return n;
}

void ChainRunner::runRound(uint64_t roundLength, ProgressReporter& progress) {
    ctx_.pool.parallelFor(chains_.size(), [&](size_t k) {
        Chain& c = *chains_[k];
        uint64_t steps = std::min(roundLength, c.plan.mutations - c.done);
        if (c.done == 0) c.startType = c.markov.state().type;  // after the burn-in
        const int w = ctx_.settings.width, h = ctx_.settings.height;
        auto splat = [&](Vec2f raster, PathType type, Rgb value) {
            forEachTentPixel(raster, w, h, [&](int x, int y, float weight) {
                const Rgb share = value * weight;
                for (Film* film : c.films) film->addSampleShared(x, y, type, share);
            });
        };
        for (uint64_t i = 0; i < steps; ++i) {
            if ((i & 63) == 0) ctx_.throwIfCancelled();
            if (c.markov.stepDeferred(splat)) {
                c.lastMove = c.done + i + 1;
                c.leftStartType = c.leftStartType || c.markov.state().type != c.startType;
            }
        }
        c.markov.flush(splat);  // the round's films are complete (previews, a shard's end)
        c.done += steps;
        progress.advance(double(steps));
    });
}

uint64_t ChainRunner::typeBoundChains(int group) const {
    uint64_t bound = 0;
    for (const auto& c : chains_)
        if ((group < 0 || c->plan.group == uint32_t(group)) && c->done > 0 && !c->leftStartType)
            ++bound;
    return bound;
}

uint64_t ChainRunner::stuckChains(int group) const {
    uint64_t stuck = 0;
    for (const auto& c : chains_)
        if ((group < 0 || c->plan.group == uint32_t(group)) && c->done > 0 &&
            c->lastMove <= c->done / 2)
            ++stuck;
    return stuck;
}

void ChainRunner::publishProgressValues(ProgressReporter& progress) const {
    std::map<std::string, double> values;
    values["mutations"] = double(mutationsDone());
    for (const auto& [name, m] : mutationStats())
        if (m.proposed > 0) values["acceptance_" + name] = double(m.accepted) / double(m.proposed);
    progress.setValues(std::move(values));
}

std::vector<Film*> ChainRunner::filmsOf(uint32_t group, bool oddHalf) {
    if (layout_ == FilmLayout::PerGroup) return {&films_[group]};
    if (layout_ == FilmLayout::PerGroupWithHalves) {
        // The odd half's film gets the same fixed-point splats: all less it is the even half.
        if (oddHalf) return {&films_[group], &films_[plan_.groups.size() + group]};
        return {&films_[group]};
    }
    // Every chain into film 0, and group 1's also into film 1: each splat is rounded to fixed
    // point on its own, the same in both films, so film 0 = group 0 + group 1 exactly.
    if (group == 1) return {&films_[0], &films_[1]};
    return {&films_[0]};
}

float ChainRunner::filmScale(double b, int width, int height, uint64_t done) {
    double pixels = double(width) * height;
    // paper Eq. 9's I_i = (b_i / N_i) sum h(x) f(x) / f*(x), with h the tent filter times the
    // pixel count (the camera's importance is normalised over the whole image).
    return done > 0 ? float(b * pixels / double(done)) : 0.0f;
}

float ChainRunner::groupScale(uint32_t group) const {
    return filmScale(plan_.groups[group].b, ctx_.settings.width, ctx_.settings.height,
                     mutationsDone(int(group)));
}

LayeredImage ChainRunner::resolveGroup(uint32_t group, ThreadPool* pool) const {
    return films_[group].resolve(groupScale(group), ctx_.settings.maxTypeLayers, pool);
}

LayeredImage ChainRunner::takeResolvedGroup(uint32_t group, ThreadPool* pool) {
    return films_[group].takeResolved(groupScale(group), ctx_.settings.maxTypeLayers, pool);
}

Image ChainRunner::resolveGroupCombined(uint32_t group) const {
    return films_[group].resolveCombined(groupScale(group));
}

Image ChainRunner::takeGroupCombined(uint32_t group) {
    Image image = resolveGroupCombined(group);
    films_[group].release();
    if (layout_ == FilmLayout::PerGroupWithHalves) films_[plan_.groups.size() + group].release();
    return image;
}

uint64_t ChainRunner::mutationsDone(int group) const {
    uint64_t n = 0;
    for (const auto& c : chains_)
        if (group < 0 || c->plan.group == uint32_t(group)) n += c->done;
    return n;
}

std::vector<std::pair<std::string, MutationStats>> ChainRunner::mutationStats(int group) const {
    // By name, in the order first seen: chains of different groups may have different sets
    // (guided's partitions keep the guided or the lens perturbation).
    std::vector<std::pair<std::string, MutationStats>> out;
    for (const auto& c : chains_) {
        if (group >= 0 && c->plan.group != uint32_t(group)) continue;
        const auto& stats = c->markov.stats();
        for (size_t i = 0; i < stats.size() && i < c->mutations.weighted.size(); ++i) {
            const std::string name = c->mutations.weighted[i].mutation->name();
            auto entry = std::find_if(out.begin(), out.end(),
                                      [&](const auto& e) { return e.first == name; });
            if (entry == out.end())
                entry = out.insert(out.end(), std::make_pair(name, MutationStats{}));
            entry->second.proposed += stats[i].proposed;
            entry->second.accepted += stats[i].accepted;
            entry->second.acceptance += stats[i].acceptance;
        }
    }
    return out;
}

uint64_t ChainRunner::halfMutationsDone(uint32_t group, bool odd) const {
    uint64_t n = 0;
    for (const auto& c : chains_)
        if (c->plan.group == group && c->oddHalf == odd) n += c->done;
    return n;
}

ErrorSums ChainRunner::halvesError(uint32_t group) const {
    const int w = ctx_.settings.width, h = ctx_.settings.height;
    if (films_[group].width() != w) return {};  // taken (takeGroupCombined): no sums left
    switch (layout_) {
        case FilmLayout::AllAndHalf:
            return filmHalvesError(films_[0], films_[1], plan_.groups[0].b, w, h, mutationsDone(0),
                                   mutationsDone(1));
        case FilmLayout::PerGroupWithHalves:
            return filmHalvesError(films_[group], films_[plan_.groups.size() + group],
                                   plan_.groups[group].b, w, h, halfMutationsDone(group, false),
                                   halfMutationsDone(group, true));
        case FilmLayout::PerGroup:
            break;
    }
    return {};
}

std::pair<Image, Image> filmHalves(const Film& all, const Film& half, double b, int width,
                                   int height, uint64_t mutationsA, uint64_t mutationsB) {
    const float scaleA = ChainRunner::filmScale(b, width, height, mutationsA);
    Image a = all.resolveCombined(scaleA);  // (A + B) scaled as A
    const Image halfAsA = half.resolveCombined(scaleA);
    for (size_t i = 0; i < a.rgb.size(); ++i) a.rgb[i] -= halfAsA.rgb[i];
    return {std::move(a),
            half.resolveCombined(ChainRunner::filmScale(b, width, height, mutationsB))};
}

ErrorSums filmHalvesError(const Film& all, const Film& half, double b, int width, int height,
                          uint64_t mutationsA, uint64_t mutationsB) {
    if (mutationsA == 0 || mutationsB == 0) return {};
    const auto [a, halfB] = filmHalves(all, half, b, width, height, mutationsA, mutationsB);
    return halvesError(a, halfB, double(mutationsA), double(mutationsB));
}

uint64_t ChainRunner::rays(int group) const {
    uint64_t n = 0;
    for (const auto& c : chains_)
        if (group < 0 || c->plan.group == uint32_t(group)) n += c->markov.rays();
    return n;
}

}  // namespace partita
