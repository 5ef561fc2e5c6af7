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

TypePattern TypePattern::exactly(const PathType& t) {
    TypePattern p;
    p.runs_ = runsOf(t);
    return p;
}

TypePattern TypePattern::structureOf(const PathType& t) {
    TypePattern p;
    p.runs_ = runsOf(t);
    for (Run& r : p.runs_) r = {r.specular, 1, true};
    return p;
}

bool TypePattern::parse(const std::string& text, TypePattern& out) {
    if (text.size() < 2 || text.front() != 'L' || text.back() != 'E') return false;
    TypePattern p;
    for (size_t i = 1; i + 1 < text.size(); ++i) {
        const char c = text[i];
        if (c == '+') {
            if (p.runs_.empty() || p.runs_.back().open) return false;
            p.runs_.back().open = true;
            continue;
        }
        if (c != 'S' && c != 'D') return false;
        const bool specular = c == 'S';
        if (!p.runs_.empty() && p.runs_.back().specular == specular) {
            if (p.runs_.back().open) return false;  // "S+S": not a maximal run
            ++p.runs_.back().length;
        } else {
            p.runs_.push_back({specular, 1, false});
        }
    }
    int vertices = 0;
    for (const Run& r : p.runs_) vertices += r.length;
    if (vertices > PathType::kMaxScatteringVertices) return false;
    out = p;
    return true;
}

bool TypePattern::matches(const PathType& t) const {
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

bool TypePattern::isExact() const {
    for (const Run& r : runs_)
        if (r.open) return false;
    return true;
}

PathType TypePattern::exactType() const {
    std::vector<bool> lightToEye;
    for (const Run& r : runs_) lightToEye.insert(lightToEye.end(), size_t(r.length), r.specular);
    PathType t;  // built camera side first
    for (auto it = lightToEye.rbegin(); it != lightToEye.rend(); ++it) t = t.withVertex(*it);
    return t;
}

std::string TypePattern::toString() const {
    std::string s = "L";
    for (const Run& r : runs_) {
        s.append(size_t(r.length), r.specular ? 'S' : 'D');
        if (r.open) s += '+';
    }
    return s + 'E';
}

std::pair<TypePattern, TypePattern> TypePattern::split(size_t i) const {
    TypePattern exact = *this, longer = *this;
    exact.runs_[i].open = false;
    ++longer.runs_[i].length;
    return {exact, longer};
}

}  // namespace partita
