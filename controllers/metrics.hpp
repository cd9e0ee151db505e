// Load-balance metrics of one interval (paper eq. 7 and the training loss's relative imbalance).
#pragma once
#include <span>

namespace semlb {

// I_global = (T_max - T_min) / T_mean; 0 when every time is 0.
double global_imbalance(std::span<const double> times);
// (T_max - T_mean) / T_mean; 0 when every time is 0.
double max_over_mean(std::span<const double> times);

}  // namespace semlb
