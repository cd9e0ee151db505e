// Per-slice workload forecasters used by the forecast-then-repartition policies (persistence, holt).
#pragma once
#include <span>
#include <vector>

namespace semlb {

// Holt's linear (double exponential) smoothing applied independently to each slice.
//   level_t = a y_t + (1-a)(level_{t-1} + trend_{t-1});  trend_t = b (level_t - level_{t-1}) + (1-b) trend_{t-1}
//   forecast = max(0, level_t + trend_t);  first observation: level = y, trend = 0.
class HoltForecaster {
 public:
  HoltForecaster(double alpha, double beta);
  // Feeds one observation vector and returns the one-step-ahead forecast.
  std::vector<double> update(std::span<const double> observed);
  // The smoothing state [slices] each (empty before the first update); restore() takes it back (InputError
  // if the two sizes differ).
  const std::vector<double>& level() const { return level_; }
  const std::vector<double>& trend() const { return trend_; }
  void restore(std::vector<double> level, std::vector<double> trend);

 private:
  double alpha_, beta_;
  std::vector<double> level_, trend_;
};

}  // namespace semlb
