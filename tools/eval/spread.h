// Mean and spread of one figure over independent seeds.
#pragma once

#include <cmath>
#include <vector>

namespace partita::eval {

struct Spread {
    double mean = 0;
    double std = 0;  // sample standard deviation (n - 1); 0 for fewer than two values
};

inline Spread spreadOf(const std::vector<double>& values) {
    Spread s;
    if (values.empty()) return s;
    for (double v : values) s.mean += v;
    s.mean /= double(values.size());
    if (values.size() < 2) return s;
    double sq = 0;
    for (double v : values) sq += (v - s.mean) * (v - s.mean);
    s.std = std::sqrt(sq / double(values.size() - 1));
    return s;
}

}  // namespace partita::eval
