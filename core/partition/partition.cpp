#include "partition/partition.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace partita {

bool Partition::holds(const PathType& t) const {
    bool listed = std::find(types.begin(), types.end(), t) != types.end();
    return complement ? !listed : listed;
}

namespace {

/// The relative standard error of b = S1 / N from N samples whose values sum to S1 and whose
/// squares sum to S2: sqrt(S2 / S1^2 - 1 / N) (the samples' variance over N, over b^2).
double relativeError(double s1, double s2, double n) {
    if (!(s1 > 0)) return INFINITY;
    return std::sqrt(std::max(0.0, s2 / (s1 * s1) - 1.0 / n));
}

}  // namespace

std::vector<Partition> makePartitions(const PrepassResult& prepass, int k,
                                      double maxRelativeError) {
    std::vector<std::pair<PathType, double>> ranked(prepass.gamma.begin(), prepass.gamma.end());
    // Largest gamma first; the map's order (type order) breaks ties, deterministically.
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    auto sumB = [&](const PathType& t) {
        auto it = prepass.sumB.find(t);
        return it == prepass.sumB.end() ? 0.0 : it->second;
    };
    double nB = double(std::max<uint64_t>(1, prepass.samplesB));
    auto bError = [&](const PathType& t) {
        auto it = prepass.sumSquaresB.find(t);
        return relativeError(sumB(t), it == prepass.sumSquaresB.end() ? 0.0 : it->second, nB);
    };
    std::vector<Partition> out;
    Partition complement;
    complement.label = kComplementLabel;
    complement.complement = true;
    for (const auto& [type, gamma] : ranked) {
        double error = bError(type);  // infinite without a half-B path
        if (int(out.size()) < k && gamma > 0 && error <= maxRelativeError) {
            Partition p;
            p.label = type.toString();
            p.types = {type};
            p.gamma = gamma;
            p.b = sumB(type) / nB;
            p.bError = error;
            out.push_back(p);
            complement.types.push_back(type);  // what the complement excludes
        } else {
            complement.gamma += gamma;
        }
    }
    // The complement's b: half B's paths of every type not taken, those absent from half A too.
    double takenB = 0, allB = 0;
    for (const Partition& p : out) takenB += p.b * nB;
    for (const auto& [type, c] : prepass.sumB) allB += c;
    complement.b = std::max(0.0, allB - takenB) / nB;
    // Types seen only in half B still need mutations: rank the complement by its half-B sum.
    if (complement.gamma <= 0) complement.gamma = complement.b * nB;
    if (complement.b > 0) out.push_back(complement);
    double total = 0;
    for (const Partition& p : out) total += p.gamma;
    for (Partition& p : out) p.p = total > 0 ? p.gamma / total : 0;
    return out;
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
