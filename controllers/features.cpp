// GRU input features: the exact formulas and clamps (docs/controllers.md mirrors this file).
#include "features.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/errors.hpp"
#include "metrics.hpp"
#include "observation.hpp"
#include "partition.hpp"
#include "reactive.hpp"

namespace semlb {
namespace {
double clamp(double v, double lo, double hi) { return std::clamp(v, lo, hi); }
}  // namespace

const char* feature_set_name(FeatureSet set) { return set == FeatureSet::v1 ? kFeatureSet : kFeatureSetV2; }

FeatureSet parse_feature_set(const std::string& name, const std::string& where) {
  if (name == kFeatureSet) return FeatureSet::v1;
  if (name == kFeatureSetV2) return FeatureSet::v2;
  throw InputError(where + "'" + name + "' is not a feature set (" + kFeatureSet + ", " + kFeatureSetV2 + ")");
}

FeatureVector boundary_features(const BoundaryState& s, FeatureSet set) {
  const double mw = std::max(s.mean_width, 1.0);
  const double angle = 2.0 * std::numbers::pi * s.growth_phase;
  const bool v2 = set == FeatureSet::v2;
  auto signed_unit = [&](double x) {
    return v2 ? x / (1.0 + std::fabs(x)) : clamp(x, -1.0, 1.0);
  };  // v1 clamps, v2 squashes
  return {
      signed_unit(s.local_imbalance),
      signed_unit(s.local_imbalance - s.prev_local_imbalance),
      v2 ? s.global_imbalance / (1.0 + s.global_imbalance) : clamp(s.global_imbalance, 0.0, 2.0),
      clamp(s.width_left / mw, 0.0, 4.0),
      clamp(s.width_right / mw, 0.0, 4.0),
      clamp((s.width_left - s.min_width) / mw, 0.0, 4.0),
      clamp((s.width_right - s.min_width) / mw, 0.0, 4.0),
      signed_unit(s.last_move / (0.25 * mw)),
      std::sin(angle),
      std::cos(angle),
      s.growth_event ? 1.0 : 0.0,
      clamp(s.proposal / std::max(s.ds_max, 1e-12), -1.0, 1.0),
  };
}

std::vector<BoundaryInputs> FeatureTracker::observe(const Observation& obs, const ReactiveParams& p) {
  const auto proposals = reactive_proposals(obs, p);
  if (!started_) {
    for (const auto& pr : proposals) prev_imbalance_.push_back(pr.local_imbalance);
    prev_boundaries_ = obs.boundaries;
    started_ = true;
  }
  if (proposals.size() != prev_imbalance_.size())
    throw InputError("event " + std::to_string(obs.event) + ": gru: the number of boundaries changed from " +
                     std::to_string(prev_imbalance_.size()) + " to " + std::to_string(proposals.size()));
  const auto w = widths(obs.boundaries, obs.slices);
  const double gimb = global_imbalance(obs.times);
  std::vector<BoundaryInputs> out(proposals.size());
  for (size_t i = 0; i < proposals.size(); ++i) {
    const auto& pr = proposals[i];
    BoundaryState s;
    s.local_imbalance = pr.local_imbalance;
    s.prev_local_imbalance = prev_imbalance_[i];
    s.global_imbalance = gimb;
    s.width_left = w[i];
    s.width_right = w[i + 1];
    s.min_width = obs.min_width;
    s.mean_width = static_cast<double>(obs.slices) / obs.ranks();
    s.last_move = obs.boundaries[i] - prev_boundaries_[i];
    s.growth_phase = obs.growth_phase;
    s.growth_event = obs.growth_event;
    s.ds_max = ds_max_frac_ * pr.n_slow;
    s.proposal = pr.direction * pr.magnitude;
    out[i] = {boundary_features(s, set_), pr.direction, pr.magnitude, s.ds_max};
    prev_imbalance_[i] = pr.local_imbalance;
  }
  prev_boundaries_ = obs.boundaries;
  return out;
}

const std::array<std::string, kFeatureCount>& feature_names() {
  static const std::array<std::string, kFeatureCount> names = {"local_imbalance",  "local_imbalance_change",
                                                               "global_imbalance", "width_left",
                                                               "width_right",      "slack_left",
                                                               "slack_right",      "last_move",
                                                               "phase_sin",        "phase_cos",
                                                               "growth_event",     "reactive_proposal"};
  return names;
}

std::string feature_list() {
  std::string s;
  for (const auto& n : feature_names()) s += (s.empty() ? "" : ",") + n;
  return s;
}

void FeatureTracker::save_state(std::map<std::string, std::vector<double>>& out) const {
  if (!started_) return;
  out["tracker.prev_imbalance"] = prev_imbalance_;
  out["tracker.prev_boundaries"].assign(prev_boundaries_.begin(), prev_boundaries_.end());
}

void FeatureTracker::load_state(const std::map<std::string, std::vector<double>>& in) {
  const auto imb = in.find("tracker.prev_imbalance"), b = in.find("tracker.prev_boundaries");
  started_ = imb != in.end();
  if (!started_) return;
  if (b == in.end() || b->second.size() != imb->second.size())
    throw InputError("gru state: tracker.prev_boundaries must accompany tracker.prev_imbalance, one per boundary");
  for (double v : b->second)
    if (v != std::floor(v) || v < 0 || v > 1e9)
      throw InputError("gru state: tracker.prev_boundaries must be slice indices");
  prev_imbalance_ = imb->second;
  prev_boundaries_.assign(b->second.begin(), b->second.end());
}

}  // namespace semlb
