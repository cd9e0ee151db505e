// Load-balance metrics of one interval.
#include "metrics.hpp"

#include <algorithm>
#include <numeric>

namespace semlb {
namespace {
double mean(std::span<const double> t) { return std::accumulate(t.begin(), t.end(), 0.0) / t.size(); }
}  // namespace

double global_imbalance(std::span<const double> t) {
  const double m = mean(t);
  if (m <= 0.0) return 0.0;
  const auto [lo, hi] = std::minmax_element(t.begin(), t.end());
  return (*hi - *lo) / m;
}

double max_over_mean(std::span<const double> t) {
  const double m = mean(t);
  return m <= 0.0 ? 0.0 : (*std::max_element(t.begin(), t.end()) - m) / m;
}

}  // namespace semlb
