#include "alias_table.h"

#include <cmath>

namespace partita {

AliasTable::AliasTable(std::span<const float> weights) : bins_(weights.size()) {
    const size_t n = weights.size();
    std::vector<double> w(n);
    for (size_t i = 0; i < n; ++i) {
        w[i] = (std::isfinite(weights[i]) && weights[i] > 0) ? double(weights[i]) : 0.0;
        total_ += w[i];
    }
    if (total_ <= 0) return;
    // Each bin holds mass 1/n. Scaled to that unit, an entry with mass below 1 ("small") keeps
    // its bin with probability equal to its mass and lends the rest to one entry with mass at
    // least 1 ("large"), whose remaining mass then goes back to one of the two lists.
    std::vector<double> mass(n);
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < n; ++i) {
        bins_[i].pmf = float(w[i] / total_);
        mass[i] = w[i] / total_ * double(n);
        (mass[i] < 1 ? small : large).push_back(uint32_t(i));
    }
    while (!small.empty() && !large.empty()) {
        uint32_t s = small.back(), l = large.back();
        small.pop_back();
        bins_[s].keep = mass[s];
        bins_[s].alias = l;
        mass[l] -= 1 - mass[s];
        if (mass[l] < 1) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // What is left has mass 1 up to rounding: it keeps its whole bin. A zero-weight entry never
    // does (it can be left over only through rounding); its bin goes to a positive one.
    uint32_t anyPositive = 0;
    while (w[anyPositive] <= 0) ++anyPositive;
    for (uint32_t i : large) bins_[i] = {1.0, i, bins_[i].pmf};
    for (uint32_t i : small)
        bins_[i] = w[i] > 0 ? Bin{1.0, i, bins_[i].pmf} : Bin{0.0, anyPositive, bins_[i].pmf};
}

}  // namespace partita
