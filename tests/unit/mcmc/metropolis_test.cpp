// The Metropolis-Hastings step of core/mcmc/metropolis.h on a small discrete state space, where
// everything can be computed exactly: seven states with an unnormalised target f (one state has
// f = 0 and must never be visited) and a non-symmetric proposal matrix q (rows sum to 1, some
// entries zero, one move 5 -> 0 without its reverse).
//
// Why these tests: an MCMC integrator is only correct if its chain leaves f / sum f invariant,
// and the classic mistakes (the proposal ratio inverted, f = 0 states entered, invalid proposals
// divided by) bias the image without crashing anything.
//  - The exact transition matrix built from q and acceptanceProbability satisfies detailed
//    balance to rounding; the same matrix with the ratio inverted does not (so the check can
//    fail).
//  - metropolisStep itself, run with a sampled proposal, produces states (and expected-value
//    splats) distributed as the target: a Pearson chi-square over many independent chains, which
//    are independent by construction, so the raw counts are a multinomial sample. The same chains
//    with the inverted ratio are rejected by the same test.
//  - Invalid proposals (none, f = 0, non-finite or zero ratio) are rejections, and the splat
//    weights of every step sum to 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "chi2.h"
#include "mcmc/metropolis.h"
#include "rng.h"

namespace partita {
namespace {

// Three chi-square tests of correct code in this file share a family-wise level of 1e-3.
constexpr double kFamilyAlpha = 1e-3;
constexpr int kChi2Tests = 3;

constexpr int kStates = 7;
constexpr int kZeroState = 6;
constexpr std::array<double, kStates> kTarget = {1, 3, 0.5, 7, 2, 4, 0};
// Unnormalised proposal weights, row x = from x: a biased walk with jumps. Integer weights so
// that sampling a row with a uniform is exact. q(5 -> 0) > 0 but q(0 -> 5) = 0: that move has a
// zero reverse density and must always be rejected.
constexpr int kProposalWeights[kStates][kStates] = {
    {1, 5, 0, 2, 0, 0, 2},  //
    {2, 0, 5, 0, 1, 0, 0},  //
    {0, 2, 1, 5, 0, 3, 1},  //
    {3, 0, 2, 0, 5, 0, 1},  //
    {0, 1, 0, 2, 1, 5, 0},  //
    {1, 0, 3, 0, 2, 0, 5},  //
    {5, 0, 1, 1, 0, 2, 1},
};

using Distribution = std::array<double, kStates>;
using Matrix = std::array<Distribution, kStates>;

int rowWeight(int x) {
    int sum = 0;
    for (int y = 0; y < kStates; ++y) sum += kProposalWeights[x][y];
    return sum;
}

double proposalProbability(int x, int y) { return double(kProposalWeights[x][y]) / rowWeight(x); }

/// y drawn from q(x -> .) with the uniform u in [0, 1); zero-weight entries are never chosen.
int sampleProposal(int x, float u) {
    double scaled = double(u) * rowWeight(x);
    int cumulative = 0;
    for (int y = 0; y < kStates; ++y) {
        cumulative += kProposalWeights[x][y];
        if (scaled < cumulative) return y;
    }
    return kStates - 1;  // unreachable: u < 1
}

Distribution targetDistribution() {
    double sum = 0;
    for (double f : kTarget) sum += f;
    Distribution pi{};
    for (int x = 0; x < kStates; ++x) pi[x] = kTarget[x] / sum;
    return pi;
}

enum class Ratio { Correct, Inverted };

/// The ratio metropolisStep expects, T(y->x) / T(x->y), or the classic mistake, its inverse.
double proposalRatio(int x, int y, Ratio ratio) {
    double forward = proposalProbability(x, y), reverse = proposalProbability(y, x);
    return ratio == Ratio::Correct ? reverse / forward : forward / reverse;
}

/// The exact transition matrix of metropolisStep: P(x, y) = q(x, y) a(x, y) for y != x, the
/// rejected mass on the diagonal.
Matrix transitionMatrix(Ratio ratio) {
    Matrix p{};
    for (int x = 0; x < kStates; ++x) {
        double moved = 0;
        for (int y = 0; y < kStates; ++y) {
            if (y == x || kProposalWeights[x][y] == 0) continue;
            double a = acceptanceProbability(kTarget[x], kTarget[y], proposalRatio(x, y, ratio));
            p[x][y] = proposalProbability(x, y) * a;
            moved += p[x][y];
        }
        p[x][x] = 1 - moved;
    }
    return p;
}

Distribution step(const Distribution& d, const Matrix& p) {
    Distribution next{};
    for (int x = 0; x < kStates; ++x)
        for (int y = 0; y < kStates; ++y) next[y] += d[x] * p[x][y];
    return next;
}

/// |a - b| relative to the larger of the two; 0 when both are 0.
double relativeDifference(double a, double b) {
    double scale = std::max(std::abs(a), std::abs(b));
    return scale == 0 ? 0 : std::abs(a - b) / scale;
}

/// max over pairs of the relative difference of pi(x) P(x, y) and pi(y) P(y, x).
double detailedBalanceViolation(const Matrix& p, const Distribution& pi) {
    double worst = 0;
    for (int x = 0; x < kStates; ++x)
        for (int y = 0; y < kStates; ++y)
            worst = std::max(worst, relativeDifference(pi[x] * p[x][y], pi[y] * p[y][x]));
    return worst;
}

/// max over states of the relative difference of (pi P)(y) and pi(y).
double stationarityViolation(const Matrix& p, const Distribution& pi) {
    Distribution next = step(pi, p);
    double worst = 0;
    for (int y = 0; y < kStates; ++y) worst = std::max(worst, relativeDifference(next[y], pi[y]));
    return worst;
}

TEST(Metropolis, TransitionMatrixSatisfiesDetailedBalance) {
    const Distribution pi = targetDistribution();
    const Matrix p = transitionMatrix(Ratio::Correct);
    for (int x = 0; x < kStates; ++x) {
        double rowSum = 0;
        for (int y = 0; y < kStates; ++y) {
            EXPECT_GE(p[x][y], 0) << x << " -> " << y;
            rowSum += p[x][y];
        }
        EXPECT_NEAR(rowSum, 1, 1e-15) << "row " << x;
        if (x != kZeroState) {
            EXPECT_EQ(p[x][kZeroState], 0) << x << " enters the f = 0 state";
        }
    }
    EXPECT_EQ(p[5][0], 0) << "a move without reverse density was accepted";
    EXPECT_LE(detailedBalanceViolation(p, pi), 1e-12);
    EXPECT_LE(stationarityViolation(p, pi), 1e-12);

    // The inverted ratio T(x->y) / T(y->x) breaks both, by far more than rounding.
    const Matrix wrong = transitionMatrix(Ratio::Inverted);
    EXPECT_GT(detailedBalanceViolation(wrong, pi), 0.1);
    EXPECT_GT(stationarityViolation(wrong, pi), 0.01);
}

// The independence (large-step) mutation on the same space: y drawn from a fixed density p(y)
// whatever x is, ratio p(x) / p(y) (mcmc/independence_mutation.h), chosen at a fixed rate and the
// walk q otherwise (mcmc/markov_chain.h: the choice's probability is the same at x and y, so it
// does not enter the ratio). p puts mass on the f = 0 state too, as a fresh path may carry no
// light.
constexpr std::array<double, kStates> kIndependentDensity = {0.05, 0.3, 0.1, 0.1, 0.2, 0.05, 0.2};
constexpr double kLargeStepRate = 0.3;

/// The exact transition matrix of the mixture; `withDensityRatio` false: p(x) / p(y) left out.
Matrix largeStepMixture(bool withDensityRatio) {
    Matrix walk = transitionMatrix(Ratio::Correct), p{};
    for (int x = 0; x < kStates; ++x) {
        double moved = 0;
        for (int y = 0; y < kStates; ++y) {
            if (y == x) continue;
            double ratio = withDensityRatio ? kIndependentDensity[x] / kIndependentDensity[y] : 1.0;
            double a = acceptanceProbability(kTarget[x], kTarget[y], ratio);
            p[x][y] =
                kLargeStepRate * kIndependentDensity[y] * a + (1 - kLargeStepRate) * walk[x][y];
            moved += p[x][y];
        }
        p[x][x] = 1 - moved;
    }
    return p;
}

TEST(Metropolis, IndependenceProposalAtAFixedRateSatisfiesDetailedBalance) {
    const Distribution pi = targetDistribution();
    const Matrix p = largeStepMixture(true);
    for (int x = 0; x < kStates; ++x)
        if (x != kZeroState) {
            EXPECT_EQ(p[x][kZeroState], 0) << x << " enters the f = 0 state";
        }
    EXPECT_GT(p[5][0], 0) << "the independence proposal reaches what the walk cannot";
    EXPECT_LE(detailedBalanceViolation(p, pi), 1e-12);
    EXPECT_LE(stationarityViolation(p, pi), 1e-12);
    // Without p(x) / p(y) the chain targets f p, not f: caught.
    const Matrix wrong = largeStepMixture(false);
    EXPECT_GT(detailedBalanceViolation(wrong, pi), 0.1);
    EXPECT_GT(stationarityViolation(wrong, pi), 0.01);
}

// The chains: kChains independent chains (one Rng stream each), all started in kStartState (the
// lowest positive f, far from where the target's mass is) and run for kChainSteps steps. Each
// contributes its final state to `finalStates` and the splats of its last step to
// `finalSplats`. Independent chains make the final states an exact multinomial sample of the
// distribution after kChainSteps steps, which the test shows is the target to within a
// negligible distance (no correlated counts enter the statistic).
constexpr int kChains = 20000;
constexpr int kChainSteps = 40;
constexpr int kStartState = 2;

struct ChainTally {
    Distribution finalStates{}, finalSplats{};
    std::array<long, kStates> visits{};
    long zeroWeightSplats = 0, zeroStateSplats = 0;
    double maxStepWeightError = 0;  // |sum of a step's splat weights - 1|
};

void runChain(uint64_t stream, Ratio ratio, ChainTally& tally) {
    Rng rng(2024, stream);
    int x = kStartState;
    double fx = kTarget[x];
    auto propose = [ratio](const int& from, Rng& r) {
        int y = sampleProposal(from, r.nextFloat());
        return Proposal<int>{true, y, kTarget[y], proposalRatio(from, y, ratio)};
    };
    for (int i = 0; i < kChainSteps; ++i) {
        bool last = i == kChainSteps - 1;
        double stepWeight = 0;
        auto splat = [&](const int& s, double weight) {
            if (weight == 0) ++tally.zeroWeightSplats;
            if (s == kZeroState) ++tally.zeroStateSplats;
            stepWeight += weight;
            if (last) tally.finalSplats[s] += weight;
        };
        metropolisStep(x, fx, rng, propose, splat);
        ++tally.visits[x];
        tally.maxStepWeightError = std::max(tally.maxStepWeightError, std::abs(stepWeight - 1));
    }
    tally.finalStates[x] += 1;
}

ChainTally runChains(Ratio ratio) {
    ChainTally tally;
    for (int c = 0; c < kChains; ++c) runChain(uint64_t(c), ratio, tally);
    return tally;
}

/// Pearson's noncentrality kChains * sum (p - pi)^2 / pi of the exact distribution after
/// kChainSteps steps from kStartState: how far the statistic's mean sits above a sample of pi.
double burnInNoncentrality() {
    const Matrix p = transitionMatrix(Ratio::Correct);
    const Distribution pi = targetDistribution();
    Distribution d{};
    d[kStartState] = 1;
    for (int i = 0; i < kChainSteps; ++i) d = step(d, p);
    double lambda = 0;
    for (int x = 0; x < kStates; ++x)
        if (pi[x] > 0) lambda += kChains * (d[x] - pi[x]) * (d[x] - pi[x]) / pi[x];
    return lambda;
}

TEST(Metropolis, ChainMatchesTargetChiSquare) {
    // The chains have forgotten their start: the exact distribution after kChainSteps differs
    // from the target by a noncentrality far below the statistic's own spread (sqrt(2 dof)).
    ASSERT_LT(burnInNoncentrality(), 0.01);

    const Distribution pi = targetDistribution();
    const double level = test::sidakLevel(kFamilyAlpha, kChi2Tests);
    const ChainTally tally = runChains(Ratio::Correct);
    EXPECT_EQ(tally.visits[kZeroState], 0) << "the chain entered a state with f = 0";
    EXPECT_EQ(tally.zeroStateSplats, 0) << "a state with f = 0 was splatted";
    EXPECT_EQ(tally.zeroWeightSplats, 0);
    EXPECT_LE(tally.maxStepWeightError, 1e-15);

    test::Pearson states = test::pearson(tally.finalStates, pi, kChains);
    ASSERT_GE(states.minExpected, 5);
    EXPECT_GE(states.pValue, level) << "final states: " << states.describe();
    // The expected-value splats are E[final state | last proposal], a Rao-Blackwellised count:
    // their covariance is at most the multinomial one, so Pearson's statistic on them is
    // stochastically below chi-square(dof) and the same level is conservative.
    test::Pearson splats = test::pearson(tally.finalSplats, pi, kChains);
    EXPECT_GE(splats.pValue, level) << "final splats: " << splats.describe();

    // The same chains with the inverted ratio converge elsewhere, and the test sees it.
    const ChainTally wrong = runChains(Ratio::Inverted);
    EXPECT_LT(test::pearson(wrong.finalStates, pi, kChains).pValue, level);
    EXPECT_LT(test::pearson(wrong.finalSplats, pi, kChains).pValue, level);
}

void expectInvalidAcceptanceIsZero() {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(acceptanceProbability(1, 0, 1), 0);    // f(y) = 0
    EXPECT_EQ(acceptanceProbability(1, -2, 1), 0);   // f(y) < 0
    EXPECT_EQ(acceptanceProbability(1, nan, 1), 0);  // f(y) NaN
    EXPECT_EQ(acceptanceProbability(1, inf, 1), 0);  // f(y) infinite
    EXPECT_EQ(acceptanceProbability(1, 2, 0), 0);    // zero ratio: no way back
    EXPECT_EQ(acceptanceProbability(1, 2, -1), 0);   // negative ratio
    EXPECT_EQ(acceptanceProbability(1, 2, nan), 0);  // NaN ratio
    EXPECT_EQ(acceptanceProbability(1, 2, inf), 0);  // infinite ratio
    EXPECT_EQ(acceptanceProbability(0, 2, 1), 1);    // leave a state with f = 0
    EXPECT_EQ(acceptanceProbability(2, 1, 1), 0.5);  // the ordinary cases
    EXPECT_EQ(acceptanceProbability(2, 1, 3), 1);    //
    EXPECT_EQ(acceptanceProbability(4, 1, 0.5), 0.125);
    EXPECT_EQ(acceptanceProbability(1e-300, 1e300, 1e300), 1);  // overflowing ratio, finite inputs
}

/// One metropolisStep from state 3 with the given proposal; checks that it is a rejection that
/// splats the current state with weight 1 and draws exactly one uniform.
void expectRejection(const Proposal<int>& proposal, const std::string& what) {
    SCOPED_TRACE(what);
    int x = 3;
    double fx = kTarget[x];
    Rng rng(7, 11), reference = rng;
    reference.nextFloat();
    std::vector<std::pair<int, double>> splats;
    double a = metropolisStep(
        x, fx, rng, [&](const int&, Rng&) { return proposal; },
        [&](const int& s, double w) { splats.emplace_back(s, w); });
    EXPECT_EQ(a, 0);
    EXPECT_EQ(x, 3);
    EXPECT_EQ(fx, kTarget[3]);
    ASSERT_EQ(splats.size(), 1u);
    EXPECT_EQ(splats[0].first, 3);
    EXPECT_EQ(splats[0].second, 1);
    EXPECT_EQ(rng.nextUInt(), reference.nextUInt()) << "a step draws one uniform, whatever a is";
}

TEST(Metropolis, InvalidProposalsAreRejections) {
    expectInvalidAcceptanceIsZero();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    expectRejection(Proposal<int>{}, "no proposal");
    expectRejection(Proposal<int>{false, 4, kTarget[4], 1}, "marked invalid");
    expectRejection(Proposal<int>{true, kZeroState, 0, 1}, "f(y) = 0");
    expectRejection(Proposal<int>{true, 4, kTarget[4], nan}, "NaN ratio");
    expectRejection(Proposal<int>{true, 4, kTarget[4], inf}, "infinite ratio");
    expectRejection(Proposal<int>{true, 4, kTarget[4], 0}, "zero ratio");
    expectRejection(Proposal<int>{true, 4, nan, 1}, "NaN f(y)");
}

TEST(Metropolis, ExpectedValueWeightsSumToOne) {
    // From state 3 (f = 7) to state 4 (f = 2) with ratio 1.75: a = 0.5. Over many steps the
    // splats are always (4, a) and (3, 1 - a), and the chain moves with probability a.
    int moves = 0;
    const int steps = 1000;
    for (int i = 0; i < steps; ++i) {
        int x = 3;
        double fx = kTarget[x];
        Rng rng(99, uint64_t(i));
        double total = 0, toProposal = 0;
        double a = metropolisStep(
            x, fx, rng,
            [](const int&, Rng&) {
                return Proposal<int>{true, 4, kTarget[4], 1.75};
            },
            [&](const int& s, double w) {
                total += w;
                if (s == 4) toProposal += w;
            });
        ASSERT_EQ(a, 0.5);
        EXPECT_EQ(total, 1);
        EXPECT_EQ(toProposal, a);
        EXPECT_EQ(fx, kTarget[x]);
        moves += x == 4;
    }
    // Moves ~ Binomial(steps, 1/2): Pearson's statistic over {moved, stayed} has one dof.
    double statistic = (moves - 0.5 * steps) * (moves - 0.5 * steps) / (0.25 * steps);
    EXPECT_GE(test::chi2SurvivalProbability(statistic, 1),
              test::sidakLevel(kFamilyAlpha, kChi2Tests))
        << moves << " moves in " << steps << " steps";
}

}  // namespace
}  // namespace partita
