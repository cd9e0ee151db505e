// Exact chains-on-chains partitioning: contiguous slices -> P ranks, min bottleneck, each >= min_width.
#pragma once
#include <span>
#include <vector>

namespace semlb {

// Interior boundaries of a contiguous partition of `work` (non-negative, finite) into `ranks` parts of at
// least `min_width` slices that minimises the largest part sum exactly. Among the optimal partitions it
// places each boundary, left to right, where the cumulative work is closest to its equal share.
std::vector<int> optimal_partition(std::span<const double> work, int ranks, int min_width);

// The partition nearest to `current` (least migration, sum of |b - current|) among those whose every part
// sum is at most `bound` and every width at least min_width. Throws InputError when none exists.
std::vector<int> nearest_partition(std::span<const double> work, std::span<const int> current, int min_width,
                                   double bound);

// Largest part sum of a partition.
double bottleneck(std::span<const double> work, std::span<const int> boundaries);

}  // namespace semlb
