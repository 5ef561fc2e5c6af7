// Classes of path types (partition/type_pattern.h) and the partitions built from them
// (partition.h, issue #23 2): what a pattern holds, checked against every type up to a length;
// the greedy construction on a pre-pass with known gamma; the partitions covering path space
// exactly once; and the Metropolis step restricted to a class on a discrete state space (every
// type up to five scattering vertices), whose exact transition matrix must keep detailed balance
// with the restricted target and never enter a type outside the class.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "mcmc/metropolis.h"
#include "partition/partition.h"
#include "partition/type_pattern.h"

namespace partita {
namespace {

/// Every type of at most `maxVertices` scattering vertices, in type order.
std::vector<PathType> allTypes(int maxVertices) {
    std::vector<PathType> out{PathType()};
    for (size_t i = 0; i < out.size(); ++i)
        if (out[i].scatteringVertices() < maxVertices) {
            out.push_back(out[i].withVertex(false));
            out.push_back(out[i].withVertex(true));
        }
    std::sort(out.begin(), out.end());
    return out;
}

PathType typeOf(const std::string& s) {
    PathType t;
    EXPECT_TRUE(PathType::parse(s, t)) << s;
    return t;
}

TypePattern patternOf(const std::string& s) {
    TypePattern p;
    EXPECT_TRUE(TypePattern::parse(s, p)) << s;
    return p;
}

/// The pattern as a regular expression over Heckbert strings, checked by hand: "X+" is one or
/// more X, every other letter itself. A second, independent reading of what a pattern holds.
bool matchesByHand(const std::string& pattern, const std::string& type) {
    // Expand to (letter, min, open) tokens and match greedily run by run (runs are maximal).
    size_t at = 0;
    for (size_t i = 0; i < pattern.size();) {
        const char c = pattern[i];
        size_t count = 0;
        while (i < pattern.size() && pattern[i] == c) ++i, ++count;
        const bool open = i < pattern.size() && pattern[i] == '+';
        if (open) ++i;
        size_t run = 0;
        while (at < type.size() && type[at] == c) ++at, ++run;
        if (open ? run < count : run != count) return false;
    }
    return at == type.size();
}

TEST(TypePattern, ParseAndPrintRoundTrip) {
    for (const char* text : {"LE", "LDE", "LD+E", "LS+DE", "LDD+SSE", "LSDSDSE", "LS+D+S+E"}) {
        TypePattern p;
        ASSERT_TRUE(TypePattern::parse(text, p)) << text;
        EXPECT_EQ(p.toString(), text);
    }
    TypePattern p;
    for (const char* bad : {"", "L", "E", "LXE", "L+E", "LS++E", "LS+SE", "LD+D+E", "DE", "LD"})
        EXPECT_FALSE(TypePattern::parse(bad, p)) << bad;
}

TEST(TypePattern, HoldsWhatTheRegularExpressionHolds) {
    const std::vector<PathType> types = allTypes(8);
    for (const char* text : {"LE", "LDE", "LD+E", "LS+DE", "LDD+SSE", "LS+D+E", "LD+S+D+E"}) {
        const TypePattern p = patternOf(text);
        int held = 0;
        for (const PathType& t : types) {
            const bool expected = matchesByHand(text, t.toString());
            EXPECT_EQ(p.matches(t), expected) << text << " " << t.toString();
            held += expected;
        }
        EXPECT_GT(held, 0) << text;
    }
    // Exact patterns hold their one type; a type's structure holds it.
    for (const PathType& t : types) {
        EXPECT_TRUE(TypePattern::exactly(t).isExact());
        EXPECT_EQ(TypePattern::exactly(t).exactType(), t);
        EXPECT_EQ(TypePattern::exactly(t).toString(), t.toString());
        EXPECT_TRUE(TypePattern::structureOf(t).matches(t)) << t.toString();
    }
}

TEST(TypePattern, SplitsAreDisjointAndCoverTheirParent) {
    const std::vector<PathType> types = allTypes(9);
    for (const char* text : {"LD+E", "LS+D+E", "LDD+S+E", "LD+S+D+S+E"}) {
        const TypePattern parent = patternOf(text);
        for (size_t i = 0; i < parent.runs().size(); ++i) {
            if (!parent.runs()[i].open) continue;
            auto [exact, longer] = parent.split(i);
            for (const PathType& t : types) {
                const int pieces = int(exact.matches(t)) + int(longer.matches(t));
                EXPECT_EQ(pieces, int(parent.matches(t)))
                    << text << " split at " << i << ": " << t.toString();
            }
        }
    }
}

/// A pre-pass that saw `gamma` per type (half A) and the same sums in half B, each with a
/// relative error of 0.1 (below the bound), from 100 half-B samples.
PrepassResult syntheticPrepass(const std::map<std::string, double>& gamma) {
    PrepassResult r;
    r.samplesA = r.samplesB = 100;
    for (const auto& [text, g] : gamma) {
        const PathType t = typeOf(text);
        r.gamma[t] = g;
        r.sumB[t] = g;
        r.sumSquaresB[t] = g * g * (0.01 + 1.0 / 100);
    }
    return r;
}

std::vector<std::string> labels(const std::vector<Partition>& partitions) {
    std::vector<std::string> out;
    for (const Partition& p : partitions) out.push_back(p.label);
    return out;
}

TEST(TypePattern, ClassesAreBuiltByStructureAndTheLargestIsSplit) {
    const PrepassResult pre = syntheticPrepass(
        {{"LDE", 5}, {"LDDE", 3}, {"LDDDE", 1.5}, {"LE", 4.2}, {"LSDE", 2}, {"LSSDE", 1.1}});
    using V = std::vector<std::string>;
    // Three structures: LD+E (9.5), LE (4.2), LS+D+E (3.1).
    EXPECT_EQ(labels(makePartitions(pre, 3, kMaxBRelativeError, PartitionShape::Classes)),
              (V{"LD+E", "LE", "LS+D+E"}));
    // Two: the third goes to the complement, which holds a share 3.1 / 16.8 of b.
    const std::vector<Partition> two =
        makePartitions(pre, 2, kMaxBRelativeError, PartitionShape::Classes);
    EXPECT_EQ(labels(two), (V{"LD+E", "LE", kComplementLabel}));
    EXPECT_NEAR(complementShareOfB(two), 3.1 / 16.8, 1e-12);
    // Four: LD+E splits into LDE (5) and LDD+E (4.5).
    EXPECT_EQ(labels(makePartitions(pre, 4, kMaxBRelativeError, PartitionShape::Classes)),
              (V{"LDE", "LDD+E", "LE", "LS+D+E"}));
    // Five: LDE cannot split, LDD+E (the next largest) does, into LDDE (3) and LDDD+E (1.5).
    EXPECT_EQ(labels(makePartitions(pre, 5, kMaxBRelativeError, PartitionShape::Classes)),
              (V{"LDE", "LE", "LS+D+E", "LDDE", "LDDD+E"}));
    // The exact strings, as the paper: the complement keeps what the top two leave.
    EXPECT_EQ(labels(makePartitions(pre, 2)), (V{"LDE", "LE", kComplementLabel}));
    EXPECT_NEAR(complementShareOfB(makePartitions(pre, 2)), 7.6 / 16.8, 1e-12);
}

TEST(TypePattern, ClassPartitionsCoverPathSpaceExactlyOnce) {
    const PrepassResult pre = syntheticPrepass({{"LDE", 5},
                                                {"LDDE", 3},
                                                {"LDDDE", 1.5},
                                                {"LE", 4.2},
                                                {"LSDE", 2},
                                                {"LSSDE", 1.1},
                                                {"LDSDE", 0.7}});
    const std::vector<PathType> types = allTypes(9);
    // Four structures (LD+E, LE, LS+D+E, LD+S+D+E): from k = 4 every half-B path has a class
    // and the complement (b = 0) is dropped, as with exact types when K of them hold all.
    for (int k = 1; k <= 7; ++k) {
        const std::vector<Partition> partitions =
            makePartitions(pre, k, kMaxBRelativeError, PartitionShape::Classes);
        EXPECT_EQ(partitions.back().complement, k < 4) << k;
        for (const PathType& t : types) {
            int holders = 0;
            for (const Partition& p : partitions) holders += p.holds(t);
            if (partitions.back().complement || pre.gamma.count(t))
                EXPECT_EQ(holders, 1) << "k " << k << ": " << t.toString();
            else
                EXPECT_LE(holders, 1) << "k " << k << ": " << t.toString();
        }
        double b = 0;
        for (const Partition& p : partitions) b += p.b;
        EXPECT_NEAR(b, 17.5 / 100, 1e-12) << k;  // the pre-pass's b, whole
        EXPECT_EQ(int(partitions.size()) - int(partitions.back().complement), std::min(k, 7));
    }
}

// ---- the Metropolis step restricted to a class ---------------------------------------------

/// The discrete state space: every type of at most five scattering vertices. Proposals from t:
/// flip one vertex, add one on the eye side (S or D) or remove the eye-side one, uniformly
/// among those that stay in the space. f > 0 everywhere, uneven.
struct TypeSpace {
    static constexpr int kMaxVertices = 5;
    std::vector<PathType> states = allTypes(kMaxVertices);

    size_t indexOf(const PathType& t) const {
        return size_t(std::lower_bound(states.begin(), states.end(), t) - states.begin());
    }
    double f(const PathType& t) const {
        return 1.0 + double((t.specularMask() * 7 + uint64_t(t.scatteringVertices()) * 3) % 5);
    }
    std::vector<PathType> neighbours(const PathType& t) const {
        std::vector<PathType> out;
        const int n = t.scatteringVertices();
        for (int i = 0; i < n; ++i) {
            PathType flipped;
            EXPECT_TRUE(PathType::fromBits(t.specularMask() ^ (uint64_t(1) << i), n, flipped));
            out.push_back(flipped);
        }
        if (n < kMaxVertices) {
            out.push_back(t.withVertex(false));
            out.push_back(t.withVertex(true));
        }
        if (n > 0) {
            PathType shorter;
            EXPECT_TRUE(PathType::fromBits(t.specularMask() & ((uint64_t(1) << (n - 1)) - 1), n - 1,
                                           shorter));
            out.push_back(shorter);
        }
        return out;
    }
    double q(const PathType& x, const PathType& y) const {
        const std::vector<PathType> n = neighbours(x);
        return double(std::count(n.begin(), n.end(), y)) / double(n.size());
    }
};

/// The exact transition matrix of the Metropolis step with the chains' restriction (a proposal
/// outside `holds` is rejected, mcmc/markov_chain.cpp), or without it.
std::vector<std::vector<double>> restrictedMatrix(const TypeSpace& s, const Partition& partition,
                                                  bool restricted) {
    const size_t n = s.states.size();
    std::vector<std::vector<double>> p(n, std::vector<double>(n, 0));
    for (size_t x = 0; x < n; ++x) {
        const PathType& tx = s.states[x];
        double moved = 0;
        for (const PathType& ty : s.neighbours(tx)) {
            const size_t y = s.indexOf(ty);
            if (y == x || p[x][y] > 0) continue;
            const double fy = !restricted || partition.holds(ty) ? s.f(ty) : 0;
            const double a = acceptanceProbability(s.f(tx), fy, s.q(ty, tx) / s.q(tx, ty));
            p[x][y] = s.q(tx, ty) * a;
            moved += p[x][y];
        }
        p[x][x] = 1 - moved;
    }
    return p;
}

TEST(TypePattern, MetropolisRestrictedToAClassKeepsDetailedBalance) {
    const TypeSpace space;
    Partition cls;
    cls.label = "LD+S+E";
    cls.patterns = {patternOf("LD+S+E")};
    Partition complement;
    complement.complement = true;
    complement.patterns = cls.patterns;
    for (const Partition* partition : {&cls, &complement}) {
        const size_t n = space.states.size();
        std::vector<double> pi(n, 0);  // the restricted target, normalised
        double total = 0;
        for (size_t x = 0; x < n; ++x)
            if (partition->holds(space.states[x])) total += pi[x] = space.f(space.states[x]);
        ASSERT_GT(total, 0);
        for (double& v : pi) v /= total;
        auto balance = [&](const std::vector<std::vector<double>>& p) {
            double worst = 0;  // largest |pi(x) P(x,y) - pi(y) P(y,x)| over pairs, x held
            for (size_t x = 0; x < n; ++x)
                for (size_t y = 0; y < n; ++y)
                    if (pi[x] > 0)
                        worst = std::max(worst, std::abs(pi[x] * p[x][y] - pi[y] * p[y][x]));
            return worst;
        };
        const auto p = restrictedMatrix(space, *partition, true);
        for (size_t x = 0; x < n; ++x)
            for (size_t y = 0; y < n; ++y)
                if (pi[x] > 0 && pi[y] == 0) {
                    EXPECT_EQ(p[x][y], 0) << partition->label << ": " << space.states[x].toString()
                                          << " -> " << space.states[y].toString();
                }
        EXPECT_LE(balance(p), 1e-15) << partition->label;
        // Without the restriction the same chain leaks out of the class: caught.
        EXPECT_GT(balance(restrictedMatrix(space, *partition, false)), 1e-3) << partition->label;
    }
}

}  // namespace
}  // namespace partita
