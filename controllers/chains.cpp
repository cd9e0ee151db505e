// Chains-on-chains: exact bisection over the bit patterns of doubles with an O(P*S) feasibility probe.
#include "chains.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "errors.hpp"
#include "partition.hpp"

namespace semlb {
namespace {

// suffix[j][s]: slices [s, S) split into j parts, each >= w wide with sum <= B (prefix sums p).
class SuffixFeasibility {
 public:
  SuffixFeasibility(const std::vector<double>& p, int ranks, int w) : p_(p), ranks_(ranks), w_(w) {}

  bool solve(double bound) {
    const int S = static_cast<int>(p_.size()) - 1;
    table_.assign(static_cast<size_t>(ranks_ + 1) * (S + 1), 0);
    at(0, S) = 1;
    std::vector<int> count_after(S + 2);  // count_after[e] = #{e' >= e : suffix[j-1][e']}
    for (int j = 1; j <= ranks_; ++j) {
      count_after[S + 1] = 0;
      for (int e = S; e >= 0; --e) count_after[e] = count_after[e + 1] + at(j - 1, e);
      int hi = S;  // largest e with p[e] - p[s] <= bound; non-increasing as s decreases
      for (int s = S - j * w_; s >= 0; --s) {
        while (hi > s && p_[hi] - p_[s] > bound) --hi;
        const int first = s + w_;
        at(j, s) = first <= hi && count_after[first] - count_after[hi + 1] > 0;
      }
    }
    return at(ranks_, 0);
  }
  bool feasible(int parts, int s) const { return table_[static_cast<size_t>(parts) * (p_.size()) + s]; }

 private:
  char& at(int j, int s) { return table_[static_cast<size_t>(j) * p_.size() + s]; }
  const std::vector<double>& p_;
  int ranks_, w_;
  std::vector<char> table_;
};

}  // namespace

std::vector<int> optimal_partition(std::span<const double> work, int ranks, int min_width) {
  const int S = static_cast<int>(work.size());
  if (ranks < 1 || min_width < 1 || static_cast<long>(ranks) * min_width > S)
    throw InputError("optimal_partition: cannot split " + std::to_string(S) + " slices into " +
                     std::to_string(ranks) + " ranks of width >= " + std::to_string(min_width));
  std::vector<double> p(S + 1, 0.0);
  for (int s = 0; s < S; ++s) {
    if (!std::isfinite(work[s]) || work[s] < 0.0)
      throw InputError("optimal_partition: work[" + std::to_string(s) + "] is not finite and non-negative");
    p[s + 1] = p[s] + work[s];
  }
  SuffixFeasibility probe(p, ranks, min_width);
  // Smallest feasible bound: bisection over the ordered bit patterns of non-negative doubles (exact).
  uint64_t lo = 0, hi = std::bit_cast<uint64_t>(p[S]);
  while (lo < hi) {
    const uint64_t mid = lo + (hi - lo) / 2;
    if (probe.solve(std::bit_cast<double>(mid))) hi = mid; else lo = mid + 1;
  }
  const double bound = std::bit_cast<double>(hi);
  probe.solve(bound);
  std::vector<int> b;
  int start = 0;
  for (int k = 1; k < ranks; ++k) {
    const double target = p[S] * k / ranks;
    int best = -1;
    for (int e = start + min_width; e <= S && p[e] - p[start] <= bound; ++e)
      if (probe.feasible(ranks - k, e) && (best < 0 || std::fabs(p[e] - target) < std::fabs(p[best] - target)))
        best = e;
    b.push_back(best);
    start = best;
  }
  return b;
}

double bottleneck(std::span<const double> work, std::span<const int> boundaries) {
  const auto sums = rank_sums(work, boundaries);
  return *std::max_element(sums.begin(), sums.end());
}

}  // namespace semlb
