// A class of path types written as a regular expression over Heckbert strings (issue #23 2):
// the runs of like vertices of a type, light to eye, each with its letter and its length, the
// length either exact or open ("at least"). "LS+DE" holds LSDE, LSSDE, LSSSDE, ...; "LDD+E"
// holds every type of two or more diffuse bounces and nothing else; a pattern whose runs are
// all exact is one Heckbert string ("LDSDE"). Runs are maximal: a type has exactly one run
// structure (its letters with repeats merged), so patterns of different structures are
// disjoint, and splitting an open run "at least m" into "exactly m" and "at least m + 1" gives
// two disjoint patterns whose union is the one split: partitions built this way cover path
// space exactly once (partition.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "path_type.h"

namespace partita {

class TypePattern {
  public:
    struct Run {
        bool specular = false;
        int length = 1;     // exact length, or the least one when open
        bool open = false;  // "at least length"
        auto operator<=>(const Run&) const = default;
    };

    TypePattern() = default;
    /// The pattern of exactly one type.
    static TypePattern exactly(const PathType& t);
    /// The class of every type with t's run structure (each run "at least 1").
    static TypePattern structureOf(const PathType& t);
    /// Inverse of toString: "L", then runs ("S", "SS", "S+", "DD+", ...), then "E"; false for
    /// anything else (a run must be maximal: "LSS+E" is one run, "LS+S+E" is refused).
    static bool parse(const std::string& text, TypePattern& out);

    bool matches(const PathType& t) const;
    bool isExact() const;
    /// The one type an exact pattern holds (meaningless otherwise).
    PathType exactType() const;
    /// "LS+DE": each run as its letter repeated `length` times, "+" when open.
    std::string toString() const;

    const std::vector<Run>& runs() const { return runs_; }
    /// The two patterns that open run `i` (length m) splits into: exactly m, at least m + 1.
    std::pair<TypePattern, TypePattern> split(size_t i) const;

    auto operator<=>(const TypePattern& o) const { return runs_ <=> o.runs_; }
    bool operator==(const TypePattern& o) const { return runs_ == o.runs_; }

  private:
    explicit TypePattern(std::vector<Run> runs);

    std::vector<Run> runs_;  // light to eye
    // Derived from runs_ once (matches() is the chains' restriction, called per proposal): an
    // exact pattern compares types; an open one first rejects types with too few vertices.
    bool exact_ = true;
    PathType exactType_;
    int minVertices_ = 0;
};

/// The runs of t, light to eye, all exact.
std::vector<TypePattern::Run> runsOf(const PathType& t);

}  // namespace partita
