#include "partition/type_pattern.h"

namespace partita {

std::vector<TypePattern::Run> runsOf(const PathType& t) {
    std::vector<TypePattern::Run> runs;
    // Light to eye: scattering vertex count-1 (next to the light) down to 0 (next to the eye).
    for (int i = t.scatteringVertices() - 1; i >= 0; --i) {
        const bool specular = t.isSpecular(i);
        if (!runs.empty() && runs.back().specular == specular)
            ++runs.back().length;
        else
            runs.push_back({specular, 1, false});
    }
    return runs;
}

TypePattern::TypePattern(std::vector<Run> runs) : runs_(std::move(runs)) {
    std::vector<bool> lightToEye;
    for (const Run& r : runs_) {
        exact_ = exact_ && !r.open;
        minVertices_ += r.length;
        lightToEye.insert(lightToEye.end(), size_t(r.length), r.specular);
    }
    // The type of the exact runs, built camera side first.
    for (auto it = lightToEye.rbegin(); it != lightToEye.rend(); ++it)
        exactType_ = exactType_.withVertex(*it);
}

TypePattern TypePattern::exactly(const PathType& t) { return TypePattern(runsOf(t)); }

TypePattern TypePattern::structureOf(const PathType& t) {
    std::vector<Run> runs = runsOf(t);
    for (Run& r : runs) r = {r.specular, 1, true};
    return TypePattern(std::move(runs));
}

bool TypePattern::parse(const std::string& text, TypePattern& out) {
    if (text.size() < 2 || text.front() != 'L' || text.back() != 'E') return false;
    std::vector<Run> runs;
    for (size_t i = 1; i + 1 < text.size(); ++i) {
        const char c = text[i];
        if (c == '+') {
            if (runs.empty() || runs.back().open) return false;
            runs.back().open = true;
            continue;
        }
        if (c != 'S' && c != 'D') return false;
        const bool specular = c == 'S';
        if (!runs.empty() && runs.back().specular == specular) {
            if (runs.back().open) return false;  // "S+S": not a maximal run
            ++runs.back().length;
        } else {
            runs.push_back({specular, 1, false});
        }
    }
    TypePattern p(std::move(runs));
    if (p.minVertices_ > PathType::kMaxScatteringVertices) return false;
    out = std::move(p);
    return true;
}

bool TypePattern::matches(const PathType& t) const {
    if (exact_) return t == exactType_;
    if (t.scatteringVertices() < minVertices_) return false;
    // Walk t's vertices light to eye, one run at a time, without building its runs.
    int i = t.scatteringVertices() - 1;
    for (const Run& run : runs_) {
        int length = 0;
        while (i >= 0 && t.isSpecular(i) == run.specular) {
            ++length;
            --i;
        }
        if (length == 0 || (run.open ? length < run.length : length != run.length)) return false;
    }
    return i < 0;
}

bool TypePattern::isExact() const { return exact_; }

PathType TypePattern::exactType() const { return exactType_; }

std::string TypePattern::toString() const {
    std::string s = "L";
    for (const Run& r : runs_) {
        s.append(size_t(r.length), r.specular ? 'S' : 'D');
        if (r.open) s += '+';
    }
    return s + 'E';
}

std::pair<TypePattern, TypePattern> TypePattern::split(size_t i) const {
    std::vector<Run> exact = runs_, longer = runs_;
    exact[i].open = false;
    ++longer[i].length;
    return {TypePattern(std::move(exact)), TypePattern(std::move(longer))};
}

}  // namespace partita
