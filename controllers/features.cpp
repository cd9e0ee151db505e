// GRU input features: the exact formulas and clamps (docs/controllers.md mirrors this file).
#include "features.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace semlb {
namespace {
double clamp(double v, double lo, double hi) { return std::clamp(v, lo, hi); }
}  // namespace

FeatureVector boundary_features(const BoundaryState& s) {
  const double mw = std::max(s.mean_width, 1.0);
  const double angle = 2.0 * std::numbers::pi * s.growth_phase;
  return {
      clamp(s.local_imbalance, -1.0, 1.0),
      clamp(s.local_imbalance - s.prev_local_imbalance, -1.0, 1.0),
      clamp(s.global_imbalance, 0.0, 2.0),
      clamp(s.width_left / mw, 0.0, 4.0),
      clamp(s.width_right / mw, 0.0, 4.0),
      clamp((s.width_left - s.min_width) / mw, 0.0, 4.0),
      clamp((s.width_right - s.min_width) / mw, 0.0, 4.0),
      clamp(s.last_move / (0.25 * mw), -1.0, 1.0),
      std::sin(angle),
      std::cos(angle),
      s.growth_event ? 1.0 : 0.0,
      clamp(s.proposal / std::max(s.ds_max, 1e-12), -1.0, 1.0),
  };
}

const std::array<std::string, kFeatureCount>& feature_names() {
  static const std::array<std::string, kFeatureCount> names = {
      "local_imbalance", "local_imbalance_change", "global_imbalance", "width_left", "width_right",
      "slack_left",      "slack_right",            "last_move",        "phase_sin",  "phase_cos",
      "growth_event",    "reactive_proposal"};
  return names;
}

std::string feature_list() {
  std::string s;
  for (const auto& n : feature_names()) s += (s.empty() ? "" : ",") + n;
  return s;
}

}  // namespace semlb
