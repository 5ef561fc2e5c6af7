// The partitions of path space (paper Sec. 4, Eq. 5-6, DESIGN.md): the K types with the largest
// gamma in the pre-pass's half A each form a partition; every other type forms the
// complementary partition (Eq. 6), which also gets chains. Every path belongs to exactly one.
// P(i) = gamma(i) / sum over all K + 1 partitions; b_i, the integral of f* over partition i,
// comes from half B: (1 / N_B) sum of C over its paths. A type whose half-B estimate of b_i has
// a relative standard error above a bound (default 15%) is folded into the complement, and so
// is one with no half-B path (it could not start a chain): a partition's b_i scales its whole
// image, so no number of mutations repairs a b_i that is off (measured: rare types with b_i off
// by 2-16x on pool and bathroom, docs/partitioned-study.md). A
// complement with nothing in half B is dropped (so is everything when the image is black).
#pragma once

#include <string>
#include <vector>

#include "partition/prepass.h"
#include "partition/type_pattern.h"
#include "path_type.h"

namespace partita {

struct Partition {
    std::string label;  // the pattern ("LDSDE", "LS+DE"), or "complement"
    /// What it holds: one exact type or one class (type_pattern.h); the complement: the patterns
    /// of every other partition, which it excludes.
    std::vector<TypePattern> patterns;
    bool complement = false;
    double gamma = 0;       // half A
    double p = 0;           // P(i)
    double b = 0;           // half B's estimate of the integral of f* over the partition
    double bError = 0;      // its relative standard error from half B's spread (the complement's
                            // summed type by type, as a class's)
    bool perPixel = false;  // estimated per pixel by restricted BDPT, not by chains (issue #23 1)
    /// The direct-light class (isDirectLightType: L S* E, L D S* E), always estimated per pixel,
    /// as mlt does by default: a path tracer's best case and the chains' worst (issue #22 1).
    bool direct = false;
    /// The direct-light class is a partition of its own: this one holds none of its types
    /// (every partition of a set with a `direct` one; the complement too).
    bool directApart = false;
    /// The chains' image-plane move: an index into the algorithm's alternatives
    /// (PartitionMutations::moves, partitioned_pipeline.h), chosen by the chains' pilot; 0 when
    /// there is nothing to choose.
    uint8_t move = 0;

    /// Whether a path of type t belongs here (the chains' restriction).
    bool holds(const PathType& t) const;
};

inline constexpr const char* kComplementLabel = "complement";
inline constexpr const char* kDirectLabel = "direct";

/// The bound on the relative standard error of a partition's b (the file's comment).
inline constexpr double kMaxBRelativeError = 0.15;

/// What a partition may be: one exact Heckbert string (the paper's) or a class of types.
enum class PartitionShape { Types, Classes };

/// Parses "types" or "classes" (std::invalid_argument otherwise).
PartitionShape parsePartitionShape(const std::string& name);

/// The partitions of `prepass` with up to `k` of their own (k = 0: the complement alone, which
/// is all of path space), ordered by decreasing gamma, the complement last. With `directApart`,
/// the direct-light class comes first as a partition of its own (not counted in k, always per
/// pixel, dropped when the pre-pass saw none of it), and the others are made of the other types
/// only.
/// Types: the k exact types of largest gamma. Classes (issue #23 2): the types grouped by run
/// structure (TypePattern::structureOf), then, while there are fewer than k classes, the class
/// of largest gamma split at the open run that divides its gamma most evenly ("LD+E" into
/// "LDE" and "LDD+E"); the k of largest gamma are kept. Either way a candidate whose b has a
/// relative error above the bound goes to the complement.
std::vector<Partition> makePartitions(const PrepassResult& prepass, int k,
                                      double maxRelativeError = kMaxBRelativeError,
                                      PartitionShape shape = PartitionShape::Types,
                                      bool directApart = false);

/// The complement's share of the sum of b over all partitions (0 without a complement).
double complementShareOfB(const std::vector<Partition>& partitions);

/// Mutations per partition in proportion to P(i) (the stratified form of Eq. 10), after
/// `minimum` for every partition (when n allows), so that none with b_i > 0 goes without a
/// chain (its share of the image would be lost): floor of the proportional share, the remainder
/// to the largest fractional parts (ties to the lower index).
std::vector<uint64_t> allocateMutations(const std::vector<Partition>& partitions, uint64_t n,
                                        uint64_t minimum = 0);

}  // namespace partita
