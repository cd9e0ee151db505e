// Partition model: widths, validity, the min-width truncation sweep, migration.
#include "partition.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "common/errors.hpp"

namespace semlb {

std::vector<int> widths(std::span<const int> boundaries, int slices) {
  std::vector<int> w;
  w.reserve(boundaries.size() + 1);
  int left = 0;
  for (int b : boundaries) {
    w.push_back(b - left);
    left = b;
  }
  w.push_back(slices - left);
  return w;
}

void check_partition(std::span<const int> boundaries, int slices, int min_width) {
  const long ranks = static_cast<long>(boundaries.size()) + 1;
  if (min_width < 1) throw InputError("min_width must be >= 1, got " + std::to_string(min_width));
  if (ranks * min_width > slices)
    throw InputError(std::to_string(ranks) + " ranks x min_width " + std::to_string(min_width) + " exceeds " +
                     std::to_string(slices) + " slices");
  const auto w = widths(boundaries, slices);
  for (size_t r = 0; r < w.size(); ++r)
    if (w[r] < min_width)
      throw InputError("boundaries: rank " + std::to_string(r) + " has width " + std::to_string(w[r]) +
                       " < min_width " + std::to_string(min_width));
}

std::vector<int> apply_moves(std::span<const int> boundaries, std::span<const long> moves, int slices, int min_width) {
  std::vector<int> out(boundaries.begin(), boundaries.end());
  const size_t n = out.size();
  for (size_t i = 0; i < n; ++i) {
    const long left_edge = i == 0 ? 0 : out[i - 1];                   // already moved in this sweep
    const long right_edge = i + 1 == n ? slices : boundaries[i + 1];  // not yet moved
    const long lo = left_edge + min_width, hi = right_edge - min_width;
    out[i] = static_cast<int>(std::clamp(static_cast<long>(out[i]) + moves[i], std::min(lo, hi), hi));
  }
  return out;
}

std::vector<int> apply_targets(std::span<const int> boundaries, std::span<const double> targets, int slices,
                               int min_width) {
  std::vector<long> moves(boundaries.size());
  for (size_t i = 0; i < moves.size(); ++i) moves[i] = std::lround(targets[i] - boundaries[i]);
  return apply_moves(boundaries, moves, slices, min_width);
}

std::vector<double> equal_share_targets(std::span<const double> work, int ranks) {
  const int S = static_cast<int>(work.size());
  double total = 0;
  for (double w : work) total += w;
  std::vector<double> t(ranks > 1 ? ranks - 1 : 0);
  if (!(total > 0)) {
    for (int k = 1; k < ranks; ++k) t[k - 1] = static_cast<double>(S) * k / ranks;
    return t;
  }
  double cum = 0;
  int s = 0;
  for (int k = 1; k < ranks; ++k) {
    const double goal = total * k / ranks;
    while (s < S && cum + work[s] < goal) cum += work[s++];
    t[k - 1] = s < S && work[s] > 0 ? s + (goal - cum) / work[s] : static_cast<double>(s);
  }
  return t;
}

long migration(std::span<const int> before, std::span<const int> after) {
  long m = 0;
  for (size_t i = 0; i < before.size(); ++i) m += std::labs(static_cast<long>(after[i]) - before[i]);
  return m;
}

std::vector<int> uniform_partition(int ranks, int slices) {
  std::vector<int> b;
  for (int r = 1; r < ranks; ++r) b.push_back(static_cast<int>(static_cast<long>(slices) * r / ranks));
  return b;
}

std::vector<double> rank_sums(std::span<const double> per_slice, std::span<const int> boundaries) {
  std::vector<double> sums(boundaries.size() + 1, 0.0);
  size_t r = 0;
  for (size_t s = 0; s < per_slice.size(); ++s) {
    while (r < boundaries.size() && static_cast<int>(s) >= boundaries[r]) ++r;
    sums[r] += per_slice[s];
  }
  return sums;
}

}  // namespace semlb
