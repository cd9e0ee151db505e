// Holt forecaster (per-slice level + trend smoothing).
#include "forecast.hpp"

#include <algorithm>

#include "common/errors.hpp"

namespace semlb {

HoltForecaster::HoltForecaster(double alpha, double beta) : alpha_(alpha), beta_(beta) {
  if (!(alpha > 0.0 && alpha <= 1.0) || !(beta >= 0.0 && beta <= 1.0))
    throw InputError("holt: need 0 < alpha <= 1 and 0 <= beta <= 1");
}

void HoltForecaster::restore(std::vector<double> level, std::vector<double> trend) {
  if (level.size() != trend.size()) throw InputError("holt state: level and trend differ in size");
  level_ = std::move(level);
  trend_ = std::move(trend);
}

std::vector<double> HoltForecaster::update(std::span<const double> y) {
  if (level_.size() != y.size()) {  // first observation (or the slice count changed): restart
    level_.assign(y.begin(), y.end());
    trend_.assign(y.size(), 0.0);
  } else {
    for (size_t s = 0; s < y.size(); ++s) {
      const double previous = level_[s];
      level_[s] = alpha_ * y[s] + (1.0 - alpha_) * (previous + trend_[s]);
      trend_[s] = beta_ * (level_[s] - previous) + (1.0 - beta_) * trend_[s];
    }
  }
  std::vector<double> f(y.size());
  for (size_t s = 0; s < y.size(); ++s) f[s] = std::max(0.0, level_[s] + trend_[s]);
  return f;
}

}  // namespace semlb
