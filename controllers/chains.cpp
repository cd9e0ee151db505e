// Chains-on-chains: exact bisection over the bit patterns of doubles with an O(P*S) feasibility probe.
#include "chains.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <string>

#include "common/errors.hpp"
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

// Prefix sums of `work` after checking that it can be split into `ranks` parts of width >= min_width.
std::vector<double> checked_prefix(std::span<const double> work, int ranks, int min_width, const char* who) {
  const int S = static_cast<int>(work.size());
  if (ranks < 1 || min_width < 1 || static_cast<long>(ranks) * min_width > S)
    throw InputError(std::string(who) + ": cannot split " + std::to_string(S) + " slices into " +
                     std::to_string(ranks) + " ranks of width >= " + std::to_string(min_width));
  std::vector<double> p(S + 1, 0.0);
  for (int s = 0; s < S; ++s) {
    if (!std::isfinite(work[s]) || work[s] < 0.0)
      throw InputError(std::string(who) + ": work[" + std::to_string(s) + "] is not finite and non-negative");
    p[s + 1] = p[s] + work[s];
  }
  return p;
}

}  // namespace

std::vector<int> optimal_partition(std::span<const double> work, int ranks, int min_width) {
  const auto p = checked_prefix(work, ranks, min_width, "optimal_partition");
  const int S = static_cast<int>(work.size());
  SuffixFeasibility probe(p, ranks, min_width);
  // Smallest feasible bound: bisection over the ordered bit patterns of non-negative doubles (exact).
  uint64_t lo = 0, hi = std::bit_cast<uint64_t>(p[S]);
  while (lo < hi) {
    const uint64_t mid = lo + (hi - lo) / 2;
    if (probe.solve(std::bit_cast<double>(mid)))
      hi = mid;
    else
      lo = mid + 1;
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

// f[k][x]: least sum of |b_j - current_j| over boundaries 1..k with boundary k at slice x and parts 1..k
// within the bound. The admissible previous boundaries y form a window [lo(x), x - min_width] whose ends
// never move left as x grows, so a monotone deque gives each row in O(S).
std::vector<int> nearest_partition(std::span<const double> work, std::span<const int> current, int min_width,
                                   double bound) {
  const int ranks = static_cast<int>(current.size()) + 1, S = static_cast<int>(work.size());
  const auto p = checked_prefix(work, ranks, min_width, "nearest_partition");
  bound += 1e-12 * p[S];  // a bottleneck summed in another order may differ from a prefix difference by rounding
  constexpr long kNone = std::numeric_limits<long>::max();
  std::vector<std::vector<long>> f(ranks, std::vector<long>(S + 1, kNone));
  std::vector<std::vector<int>> from(ranks, std::vector<int>(S + 1, -1));
  f[0][0] = 0;
  for (int k = 1; k < ranks; ++k) {
    std::deque<int> window;  // candidate y, f[k-1][y] increasing
    int next_y = 0, lo = 0;
    for (int x = k * min_width; x <= S - (ranks - k) * min_width; ++x) {
      for (; next_y <= x - min_width; ++next_y) {
        if (f[k - 1][next_y] == kNone) continue;
        while (!window.empty() && f[k - 1][window.back()] >= f[k - 1][next_y]) window.pop_back();
        window.push_back(next_y);
      }
      while (p[x] - p[lo] > bound) ++lo;
      while (!window.empty() && window.front() < lo) window.pop_front();
      if (window.empty()) continue;
      f[k][x] = f[k - 1][window.front()] + std::abs(x - current[k - 1]);
      from[k][x] = window.front();
    }
  }
  int best = -1;
  for (int x = (ranks - 1) * min_width; x <= S - min_width; ++x)
    if (f[ranks - 1][x] != kNone && p[S] - p[x] <= bound && (best < 0 || f[ranks - 1][x] < f[ranks - 1][best]))
      best = x;
  if (best < 0) throw InputError("nearest_partition: no partition keeps every rank within the bound");
  std::vector<int> b(ranks - 1);  // empty for one rank
  for (int k = ranks - 1; k >= 1; --k) {
    b[k - 1] = best;
    best = from[k][best];
  }
  return b;
}

}  // namespace semlb
