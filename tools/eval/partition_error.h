// The error of a partitioned render partition by partition (`partita-eval quality`). A
// `partitioned` render has one layer per partition, named by its type string ("LDSDE"), and the
// complementary partition's layer "complement" (integrators/partitioned); its statistics name
// them in order (labels partition_<g>_type). The reference of a one-type partition is the
// reference's layer of that type (references keep every type: `--layers 1024`), of a class
// ("LS+DE", partition/type_pattern.h) the sum of its types' layers, of the direct light's
// partition ("direct") the sum of the direct-light types' layers; the reference
// of the complement is the reference's combined image minus its layers of the render's K types,
// i.e. everything else, its "other" included.
//
// A partition's share of the error is its squared error summed over pixels and RGB values over
// the combined image's. The combined error is the sum of the partitions' errors, so its squared
// error is the sum of theirs plus twice the cross terms between partitions: the shares need not
// sum to 1 (the cross terms are zero in expectation only for independent partition estimates,
// and the partitions share the pre-pass).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "image.h"

namespace partita::eval {

struct PartitionError {
    std::string layer;            // the partition's type string, or "complement"
    double rmse = 0, relMse = 0;  // as image_metrics.h, against the partition's reference
    double squaredError = 0;      // sum over pixels and RGB values of (x - r)^2
    double share = 0;             // squaredError over the combined image's (0 when that is 0)
    /// False for a type the reference has no layer of: its reference is black then (or, when
    /// the reference has an "other" layer, possibly inside it); false for the complement when
    /// one of the K types is missing from a reference with an "other" (which may hold it).
    bool inReference = true;
};

/// The partitions of a render from its statistics' labels: partition_0_type, partition_1_type,
/// ... in order, until the first index that is missing. Empty for a render without partitions.
std::vector<std::string> partitionLabels(const std::map<std::string, std::string>& labels);

/// The part of `image` that partition `name` holds: its layer when `image` has one (a
/// partitioned render, or a reference's layer of a one-type partition); else the sum of the
/// layers of the types it holds: a class's types (less the direct-light types when
/// `directApart`, the render having the partition "direct"), or for "direct" the direct-light
/// types (path_type.h, isDirectLightType). `complete` false when part of it may lie in the
/// image's "other" (or it is a type the image lacks: black).
Image partitionLayer(const LayeredImage& image, const std::string& name, bool directApart,
                     bool& complete);

/// The error of each partition's layer of `render` (in the order of `partitions`) against its
/// reference (above). std::invalid_argument when the render lacks a partition's layer or the
/// sizes differ.
std::vector<PartitionError> partitionErrors(const LayeredImage& render,
                                            const std::vector<std::string>& partitions,
                                            const LayeredImage& reference);

}  // namespace partita::eval
