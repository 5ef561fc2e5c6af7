// Runs the chains of a chain plan on the thread pool (the orchestration mlt, partitioned and
// guided share): rounds of at most `roundMutations` mutations per chain, each chain adding its
// splats, tent-filtered (tent_filter.h), to its group's film as it goes
// (Film::addSampleShared: every thread at once). The films' sums are exact, so the order in
// which chains on different threads add does not matter: the films are bit-identical for any
// thread count. Cancellation is checked inside the chains.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "algorithm.h"
#include "film.h"
#include "half_split_error.h"
#include "mcmc/chain_plan.h"
#include "mcmc/markov_chain.h"
#include "mcmc/veach_mutations.h"

namespace partita {

class ProgressReporter;

class ChainRunner {
  public:
    /// The mutations of one chain of group g.
    using MutationFactory = std::function<MutationSet(uint32_t group)>;
    /// The restriction of a group's chains (empty: none).
    using RestrictionFactory = std::function<PathRestriction(uint32_t group)>;
    /// Where the chains' splats go.
    enum class FilmLayout {
        /// Film g holds group g's chains, with the plan's type layers.
        PerGroup,
        /// A plan of two halves of the same b (groups 0 and 1: mlt's chains beside the direct
        /// light): film 0 holds every chain, with the plan's type layers, and film 1 only the
        /// combined image of group 1's chains. Group 0's image is film 0 less film 1, exactly
        /// (fixed-point sums), so the halves cost one layered film, not two (issue #24).
        AllAndHalf,
        /// PerGroup, and after the groups' films one combined-only film per group holding its
        /// odd chains (every other chain of the group in plan order): group g's two halves, for
        /// its error estimate (halvesError), at 24 bytes a pixel more per group. A group
        /// without chains (a partition estimated per pixel) has empty (0x0) films: its
        /// resolveGroupCombined is an empty image.
        PerGroupWithHalves,
    };

    /// Builds every chain from the plan; std::invalid_argument when a start is not a path of
    /// this scene with f* > 0.
    ChainRunner(const RenderContext& ctx, const ChainPlan& plan, const MutationFactory& mutations,
                const RestrictionFactory& restrictions = {}, uint64_t roundMutations = 1024,
                FilmLayout layout = FilmLayout::PerGroup);
    ~ChainRunner();

    /// Runs the plan's mutations, or rounds until `seconds` have passed when seconds > 0 (then
    /// the plan's counts are upper bounds). After each round, the running acceptance of each
    /// mutation proposed so far ("acceptance_<name>", accepted / proposed) and "mutations" go
    /// into `progress` (its next report), then afterRound(elapsed seconds).
    void run(ProgressReporter& progress, double seconds,
             const std::function<void(double)>& afterRound = {});

    /// The scale of a group's film: b W H / N (N mutations done in it; 0 when none), in float as
    /// the films resolve with it. One function for the in-process image and the merged shards'.
    static float filmScale(double b, int width, int height, uint64_t done);

    /// Group g's image: its film scaled by b_g W H / N_g (the mutations done in it); PerGroup
    /// layout only.
    LayeredImage resolveGroup(uint32_t group, ThreadPool* pool) const;
    /// resolveGroup's image, consuming group g's film (its memory given back layer by layer).
    LayeredImage takeResolvedGroup(uint32_t group, ThreadPool* pool);
    /// Only the combined image of group g (no type layers), scaled the same way.
    Image resolveGroupCombined(uint32_t group) const;
    /// resolveGroupCombined's image, giving group g's films (its own and, PerGroupWithHalves,
    /// its odd half's) back to the system: a render's final image, made one group at a time so
    /// that the films and the images are not held at once. Group g resolves nothing afterwards
    /// (film(g) is 0x0, halvesError(g) no longer available): take the statistics first.
    Image takeGroupCombined(uint32_t group);
    /// Film f (group f's in the PerGroup layout; see FilmLayout).
    const Film& film(uint32_t f) const { return films_[f]; }
    size_t filmCount() const { return films_.size(); }
    /// Film f, moved out (a finished shard's result; the runner resolves no more).
    Film takeFilm(uint32_t f) { return std::move(films_[f]); }
    uint64_t mutationsDone(int group = -1) const;
    /// Per mutation name: proposed, accepted, sum of a, over all chains (of a group if >= 0).
    std::vector<std::pair<std::string, MutationStats>> mutationStats(int group = -1) const;
    /// Chains (of a group if >= 0) that moved in none of the last half of their mutations so
    /// far: stuck on a path no proposal leaves (issue #22 2). Burn-in does not count.
    uint64_t stuckChains(int group = -1) const;
    /// Chains (of a group if >= 0) whose path has kept its start's type for every mutation so
    /// far: a chain can move and still never leave a region of path space (a path between
    /// specular chains that only small perturbations change, issue #22 2).
    uint64_t typeBoundChains(int group = -1) const;
    /// Rays traced by the chains (of a group if >= 0), burn-in included.
    uint64_t rays(int group = -1) const;
    /// The estimated error of a group's image from its two halves of chains (independent
    /// chains: each half's image, resolved with b W H / its own mutations, estimates the same
    /// image; half_split_error.h). PerGroupWithHalves: group g's even and odd chains;
    /// AllAndHalf: the image of groups 0 and 1 together (pass 0). Zero sums in the PerGroup
    /// layout or while a half has no mutation. b's own error is not in it (ErrorSums::
    /// addScaleVariance). Between runs or rounds only (afterRound), not while chains run.
    ErrorSums halvesError(uint32_t group) const;
    /// Asks run() to return after the round under way (a target error reached); thread-safe.
    void requestStop() { stopRequested_ = true; }
    bool stopRequested() const { return stopRequested_; }
    /// Burn-in steps run, over all chains (a time budget's burn-in stops at its share of the
    /// time, startup_rule.h).
    uint64_t burnInSteps() const;

  private:
    /// filmScale of group g.
    float groupScale(uint32_t group) const;
    struct Chain;
    /// Every chain's burn-in steps, unsplatted; with seconds > 0 (a time budget) only until
    /// StartupRule::kBurnInShare of them have passed.
    void burnIn(double seconds);
    void runRound(uint64_t roundLength, ProgressReporter& progress);
    /// The films a chain of `group` splats into (see FilmLayout).
    std::vector<Film*> filmsOf(uint32_t group, bool oddHalf);
    /// Mutations done by the even (odd = false) or odd chains of a group.
    uint64_t halfMutationsDone(uint32_t group, bool odd) const;
    void publishProgressValues(ProgressReporter& progress) const;

    const RenderContext& ctx_;
    const ChainPlan& plan_;
    uint64_t roundMutations_;
    FilmLayout layout_;
    std::vector<std::unique_ptr<Chain>> chains_;
    std::vector<Film> films_;
    std::atomic<bool> stopRequested_{false};
};

/// The combined images of two halves of chains from their films: `all` holds both halves'
/// splats, `half` half B's alone; each half's image is its film scaled by b W H / its mutations
/// (ChainRunner::filmScale), half A's made of all less half. Both mutation counts must be > 0.
std::pair<Image, Image> filmHalves(const Film& all, const Film& half, double b, int width,
                                   int height, uint64_t mutationsA, uint64_t mutationsB);
/// The error sums of the image of both halves (halvesError of filmHalves); zero sums when a
/// half has no mutation.
ErrorSums filmHalvesError(const Film& all, const Film& half, double b, int width, int height,
                          uint64_t mutationsA, uint64_t mutationsB);

}  // namespace partita
