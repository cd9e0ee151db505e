// Exact chains-on-chains partitioning: contiguous slices -> P ranks, min bottleneck, each >= min_width.
#pragma once
#include <span>
#include <vector>

namespace semlb {

// Interior boundaries of a contiguous partition of `work` (non-negative, finite) into `ranks` parts of at
// least `min_width` slices that minimises the largest part sum exactly. Among the optimal partitions it
// places each boundary, left to right, where the cumulative work is closest to its equal share.
std::vector<int> optimal_partition(std::span<const double> work, int ranks, int min_width);

// Largest part sum of a partition.
double bottleneck(std::span<const double> work, std::span<const int> boundaries);

}  // namespace semlb
