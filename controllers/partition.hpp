// Partition model: P contiguous slice ranges given by P-1 interior boundaries, each at least min_width wide.
#pragma once
#include <span>
#include <vector>

namespace semlb {

// Widths of the P ranks; boundaries are interior (P-1 of them).
std::vector<int> widths(std::span<const int> boundaries, int slices);

// Throws InputError unless 0 < b_1 < ... < slices with every width >= min_width.
void check_partition(std::span<const int> boundaries, int slices, int min_width);

// Applies signed integer moves (positive = boundary moves right) in one left-to-right sweep. Each move is
// truncated so that both neighbouring ranks keep >= min_width given the widths after the earlier moves.
std::vector<int> apply_moves(std::span<const int> boundaries, std::span<const long> moves, int slices, int min_width);

// Moves each boundary to the nearest integer of its real-valued target (move = lround(target - b): half away
// from zero), then applies the moves with apply_moves (the min-width sweep). targets: [P-1], in slices.
std::vector<int> apply_targets(std::span<const int> boundaries, std::span<const double> targets, int slices,
                               int min_width);

// Where the cumulative work reaches k/P of its total, k = 1..P-1, in slices (real: linear within the slice that
// crosses it): the equal-share cut a prefix sum finds in O(S) (the boundaries optimal_partition places "closest to
// the equal share" without its bottleneck search). work: [S], non-negative; all zero gives the uniform positions.
std::vector<double> equal_share_targets(std::span<const double> work, int ranks);

// Migration of one rebalancing event: sum over boundaries of |b_new - b_old| (slices moved).
long migration(std::span<const int> before, std::span<const int> after);

// Equal-width geometric partition (remainder spread over the first ranks).
std::vector<int> uniform_partition(int ranks, int slices);

// Per-rank sums of per-slice values (e.g. work -> times).
std::vector<double> rank_sums(std::span<const double> per_slice, std::span<const int> boundaries);

}  // namespace semlb
