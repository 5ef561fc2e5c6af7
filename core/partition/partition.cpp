#include "partition/partition.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>

#include "half_split_error.h"

namespace partita {

bool Partition::holds(const PathType& t) const {
    if (direct) return isDirectLightType(t);
    if (directApart && isDirectLightType(t)) return false;
    const bool listed = std::any_of(patterns.begin(), patterns.end(),
                                    [&](const TypePattern& p) { return p.matches(t); });
    return complement ? !listed : listed;
}

PartitionShape parsePartitionShape(const std::string& name) {
    if (name == "types") return PartitionShape::Types;
    if (name == "classes") return PartitionShape::Classes;
    throw std::invalid_argument("unknown partition shape '" + name + "' (types or classes)");
}

namespace {

/// The relative standard error of b = S1 / N from N samples whose values sum to S1 and whose
/// squares sum to S2 (half_split_error.h).
double relativeError(double s1, double s2, double n) {
    return std::sqrt(relativeVarianceOfMean(s1, s2, n));
}

double valueOr0(const std::map<PathType, double>& m, const PathType& t) {
    auto it = m.find(t);
    return it == m.end() ? 0.0 : it->second;
}

/// A would-be partition: its pattern, the pre-pass types it holds, its gamma and half B's sums
/// for its b (a class's squares summed per type, leaving out the cross terms of one sample's
/// paths of several member types: an underestimate of b's error where one sample finds
/// several, as one pt sample finds LDE and LDDE).
struct Candidate {
    TypePattern pattern;
    std::vector<PathType> members;  // in type order
    double gamma = 0, sumB = 0, sumSquaresB = 0;

    double bError(const PrepassResult& prepass) const {
        return relativeError(sumB, sumSquaresB, double(std::max<uint64_t>(1, prepass.samplesB)));
    }
    /// Whether it may be a partition: light in half A, a b of bounded error (infinite without
    /// a half-B path).
    bool usable(const PrepassResult& prepass, double maxRelativeError) const {
        return gamma > 0 && bError(prepass) <= maxRelativeError;
    }
};

Candidate candidateOf(const PrepassResult& prepass, TypePattern pattern,
                      const std::vector<PathType>& types) {
    Candidate c{std::move(pattern), {}, 0, 0, 0};
    for (const PathType& t : types)
        if (c.pattern.matches(t)) {
            c.members.push_back(t);
            c.gamma += valueOr0(prepass.gamma, t);
            c.sumB += valueOr0(prepass.sumB, t);
            c.sumSquaresB += valueOr0(prepass.sumSquaresB, t);
        }
    return c;
}

/// Every type the pre-pass saw, in either half, in type order; with `directApart`, only those
/// outside the direct-light class.
std::vector<PathType> typesSeen(const PrepassResult& prepass, bool directApart) {
    std::set<PathType> seen;
    for (const auto& [t, g] : prepass.gamma) seen.insert(t);
    for (const auto& [t, b] : prepass.sumB) seen.insert(t);
    std::vector<PathType> out;
    for (const PathType& t : seen)
        if (!directApart || !isDirectLightType(t)) out.push_back(t);
    return out;
}

std::vector<Candidate> exactCandidates(const PrepassResult& prepass, bool directApart) {
    std::vector<Candidate> out;
    for (const auto& [t, gamma] : prepass.gamma)
        if (!directApart || !isDirectLightType(t))
            out.push_back(candidateOf(prepass, TypePattern::exactly(t), {t}));
    return out;
}

/// The direct-light class's partition: gamma and b summed over its types (b's error type by
/// type, as a class's).
Partition directPartition(const PrepassResult& prepass) {
    Partition p;
    p.label = kDirectLabel;
    p.direct = true;
    p.perPixel = true;
    double sumB = 0, sumSquares = 0;
    for (const auto& [t, g] : prepass.gamma)
        if (isDirectLightType(t)) p.gamma += g;
    for (const auto& [t, b] : prepass.sumB)
        if (isDirectLightType(t)) {
            sumB += b;
            sumSquares += valueOr0(prepass.sumSquaresB, t);
        }
    const double nB = double(std::max<uint64_t>(1, prepass.samplesB));
    p.b = sumB / nB;
    p.bError = relativeError(sumB, sumSquares, nB);
    return p;
}

/// The split of c at an open run that divides its gamma most evenly, both pieces usable;
/// false when there is none.
bool bestSplit(const PrepassResult& prepass, const Candidate& c, double maxRelativeError,
               Candidate& exact, Candidate& longer) {
    double best = 0;
    for (size_t i = 0; i < c.pattern.runs().size(); ++i) {
        if (!c.pattern.runs()[i].open) continue;
        auto [e, l] = c.pattern.split(i);
        Candidate ce = candidateOf(prepass, e, c.members), cl = candidateOf(prepass, l, c.members);
        if (!ce.usable(prepass, maxRelativeError) || !cl.usable(prepass, maxRelativeError))
            continue;
        const double even = std::min(ce.gamma, cl.gamma);
        if (even > best) {
            best = even;
            exact = std::move(ce);
            longer = std::move(cl);
        }
    }
    return best > 0;
}

/// Classes: one per run structure, then the usable one of largest gamma split until k are
/// usable (or none splits).
std::vector<Candidate> classCandidates(const PrepassResult& prepass, int k, double maxRelativeError,
                                       bool directApart) {
    std::map<TypePattern, std::vector<PathType>> byStructure;
    for (const PathType& t : typesSeen(prepass, directApart))
        byStructure[TypePattern::structureOf(t)].push_back(t);
    std::vector<Candidate> out;
    for (auto& [pattern, members] : byStructure)
        out.push_back(candidateOf(prepass, pattern, members));
    auto usable = [&] {
        return std::count_if(out.begin(), out.end(), [&](const Candidate& c) {
            return c.usable(prepass, maxRelativeError);
        });
    };
    std::vector<bool> unsplittable(out.size(), false);
    while (usable() < k) {
        size_t largest = out.size();
        for (size_t i = 0; i < out.size(); ++i)
            if (!unsplittable[i] && out[i].usable(prepass, maxRelativeError) &&
                (largest == out.size() || out[i].gamma > out[largest].gamma))
                largest = i;
        if (largest == out.size()) break;
        Candidate exact, longer;
        if (!bestSplit(prepass, out[largest], maxRelativeError, exact, longer)) {
            unsplittable[largest] = true;
            continue;
        }
        out[largest] = std::move(exact);
        out.push_back(std::move(longer));
        unsplittable.push_back(false);
    }
    return out;
}

}  // namespace

std::vector<Partition> makePartitions(const PrepassResult& prepass, int k, double maxRelativeError,
                                      PartitionShape shape, bool directApart) {
    // A direct-light class the pre-pass never saw is no partition, and then no other partition
    // leaves it out: path space stays covered exactly once.
    const Partition direct = directPartition(prepass);
    directApart = directApart && (direct.gamma > 0 || direct.b > 0);
    std::vector<Candidate> ranked = shape == PartitionShape::Classes
                                        ? classCandidates(prepass, k, maxRelativeError, directApart)
                                        : exactCandidates(prepass, directApart);
    // Largest gamma first; the candidates' order (pattern or type order) breaks ties.
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const Candidate& a, const Candidate& b) { return a.gamma > b.gamma; });
    const double nB = double(std::max<uint64_t>(1, prepass.samplesB));
    std::vector<Partition> out;
    if (directApart) out.push_back(direct);
    const int most = k + int(out.size());
    Partition complement;
    complement.label = kComplementLabel;
    complement.complement = true;
    complement.directApart = directApart;
    for (const Candidate& c : ranked) {
        if (int(out.size()) < most && c.usable(prepass, maxRelativeError)) {
            Partition p;
            p.directApart = directApart;
            p.label = c.pattern.toString();
            p.patterns = {c.pattern};
            p.gamma = c.gamma;
            p.b = c.sumB / nB;
            p.bError = c.bError(prepass);
            out.push_back(p);
            complement.patterns.push_back(c.pattern);  // what the complement excludes
        } else {
            complement.gamma += c.gamma;
        }
    }
    // The complement's b: half B's paths of every type no partition took, those absent from
    // half A too (summed type by type: exactly 0 when every type has a partition).
    double restB = 0, restSquares = 0;
    for (const auto& [type, c] : prepass.sumB) {
        const PathType& t = type;  // clang 14 cannot capture a structured binding
        if (std::none_of(out.begin(), out.end(), [&](const Partition& p) { return p.holds(t); })) {
            restB += c;
            restSquares += valueOr0(prepass.sumSquaresB, type);
        }
    }
    complement.b = restB / nB;
    complement.bError = relativeError(restB, restSquares, nB);
    // Types seen only in half B still need mutations: rank the complement by its half-B sum.
    if (complement.gamma <= 0) complement.gamma = complement.b * nB;
    if (complement.b > 0) out.push_back(complement);
    double total = 0;
    for (const Partition& p : out) total += p.gamma;
    for (Partition& p : out) p.p = total > 0 ? p.gamma / total : 0;
    return out;
}

double complementShareOfB(const std::vector<Partition>& partitions) {
    double all = 0, complement = 0;
    for (const Partition& p : partitions) {
        all += p.b;
        if (p.complement) complement += p.b;
    }
    return all > 0 ? complement / all : 0;
}

std::vector<uint64_t> allocateMutations(const std::vector<Partition>& partitions, uint64_t n,
                                        uint64_t minimum) {
    if (minimum * partitions.size() > n) minimum = n / std::max<size_t>(1, partitions.size());
    std::vector<uint64_t> share(partitions.size(), minimum);
    std::vector<double> fraction(partitions.size(), 0);
    uint64_t rest = n - minimum * partitions.size(), given = minimum * partitions.size();
    for (size_t i = 0; i < partitions.size(); ++i) {
        double exact = double(rest) * partitions[i].p;
        uint64_t whole = uint64_t(std::floor(exact));
        share[i] += whole;
        fraction[i] = exact - double(whole);
        given += whole;
    }
    std::vector<size_t> order(partitions.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return fraction[a] > fraction[b]; });
    for (size_t j = 0; given < n && !order.empty(); j = (j + 1) % order.size(), ++given)
        ++share[order[j]];
    return share;
}

}  // namespace partita
