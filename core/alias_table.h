// Walker's alias method: a discrete distribution sampled in constant time, with one table
// lookup and one comparison (Vose's construction, "A linear algorithm for generating random
// numbers with a given distribution", 1991). Next-event estimation picks a light at every path
// vertex, where a binary search over a CDF costs a chain of dependent loads.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace partita {

class AliasTable {
  public:
    AliasTable() = default;
    /// Probabilities proportional to `weights`; negative, NaN and infinite weights count as 0.
    explicit AliasTable(std::span<const float> weights);

    size_t size() const { return bins_.size(); }
    /// No index can be drawn: no weights, or none positive.
    bool empty() const { return total_ <= 0; }
    float pmf(uint32_t i) const { return bins_[i].pmf; }

    /// Index i with probability pmf(i), for u in [0, 1): bin floor(u n) is chosen uniformly,
    /// and the rest of u decides between the bin's own index and its alias.
    uint32_t sample(float u) const {
        const double scaled = double(u) * double(bins_.size());  // exact: 24 bits times n
        uint32_t i = uint32_t(scaled);
        if (i >= bins_.size()) i = uint32_t(bins_.size() - 1);
        const Bin& bin = bins_[i];
        return scaled - double(i) < bin.keep ? i : bin.alias;
    }

  private:
    struct Bin {
        double keep = 0;     // probability of keeping i once bin i is chosen
        uint32_t alias = 0;  // the index drawn otherwise
        float pmf = 0;       // probability of i overall
    };
    std::vector<Bin> bins_;
    double total_ = 0;
};

}  // namespace partita
