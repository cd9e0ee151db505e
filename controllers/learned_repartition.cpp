// learned_repartition: the policy, its registration and its weights file (docs/controllers.md "learned_repartition").
#include "learned_repartition.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/errors.hpp"
#include "common/h5.hpp"
#include "common/text_io.hpp"
#include "partition.hpp"
#include "policy.hpp"

namespace semlb {
namespace {

constexpr double kMinCorrection = 0.1, kMaxCorrection = 10.0;

class LearnedRepartitionPolicy final : public Policy {
 public:
  explicit LearnedRepartitionPolicy(const RepartitionParams& p) : p_(p) {}

  std::vector<int> decide(const Observation& obs) override {
    const auto& w = require_field(obs.slice_work, obs, "learned_repartition", "slice_work");
    const int S = obs.slices, P = obs.ranks();
    if (static_cast<int>(correction_.size()) != S) correction_.assign(S, 1.0), previous_.clear();
    if (p_.gain > 0) correct(obs, w);
    std::vector<double> est(S), forecast(S);
    for (int s = 0; s < S; ++s) est[s] = w[s] * correction_[s];
    const bool trend = p_.trend > 0 && static_cast<int>(previous_.size()) == S;
    for (int s = 0; s < S; ++s)
      forecast[s] = trend ? std::max(0.0, est[s] + p_.trend * (est[s] - previous_[s])) : est[s];
    previous_ = std::move(est);
    auto targets = equal_share_targets(forecast, P);
    if (p_.deadband > 0)
      for (int k = 0; k + 1 < P; ++k)
        if (std::fabs(targets[k] - obs.boundaries[k]) < p_.deadband * S) targets[k] = obs.boundaries[k];
    if (p_.move_cost > 0 || p_.fixed_cost > 0) gate(obs, forecast, targets);
    return apply_targets(obs.boundaries, targets, S, obs.min_width);
  }

  PolicyState save_state() const override { return {{"correction", correction_}, {"previous", previous_}}; }
  void load_state(const PolicyState& s) override {
    if (s.empty()) return correction_.clear(), previous_.clear();
    if (s.size() != 2 || !s.count("correction") || !s.count("previous"))
      throw InputError("learned_repartition state: expected correction and previous");
    const auto &c = s.at("correction"), &e = s.at("previous");
    if (!e.empty() && e.size() != c.size())
      throw InputError("learned_repartition state: previous has " + std::to_string(e.size()) + " slices, correction " +
                       std::to_string(c.size()));
    for (double x : c)
      if (!(x >= kMinCorrection && x <= kMaxCorrection))
        throw InputError("learned_repartition state: correction out of range");
    correction_ = c, previous_ = e;
  }

 private:
  // Boundary k moves to its target only when that lowers the larger of its two ranks' forecast work (the others at
  // their targets) by more than move_cost sum(t)/S per slice it moves; no boundary moves unless the gains of those
  // that do sum to more than fixed_cost sum(t)/P.
  void gate(const Observation& obs, const std::vector<double>& forecast, std::vector<double>& targets) const {
    const int P = obs.ranks(), S = obs.slices;
    std::vector<double> cum(S + 1, 0.0);
    for (int s = 0; s < S; ++s) cum[s + 1] = cum[s] + forecast[s];
    std::vector<long> t(P - 1);
    for (int k = 0; k + 1 < P; ++k)
      t[k] = std::clamp(obs.boundaries[k] + std::lround(targets[k] - obs.boundaries[k]), 0L, static_cast<long>(S));
    double total = 0, gained = 0;
    for (double x : obs.times) total += x;
    bool moved = false;
    for (int k = 0; k + 1 < P; ++k) {
      const long b = obs.boundaries[k], lo = k == 0 ? 0 : t[k - 1], hi = k + 2 < P ? t[k + 1] : S;
      if (t[k] == b || b <= lo || b >= hi) {  // no move, or the old place lies outside its new neighbours: it must move
        moved = moved || t[k] != b;
        continue;
      }
      const double now = std::max(cum[b] - cum[lo], cum[hi] - cum[b]);
      const double next = std::max(cum[t[k]] - cum[lo], cum[hi] - cum[t[k]]);
      if (now - next > p_.move_cost * total / S * static_cast<double>(std::labs(t[k] - b)))
        gained += now - next, moved = true;
      else
        targets[k] = b;
    }
    if (moved && !(gained > p_.fixed_cost * total / P))
      for (int k = 0; k + 1 < P; ++k) targets[k] = obs.boundaries[k];
  }

  // c_s *= exp(gain soft(log(t_r / sum_{s in r} w_s c_s), noise_floor)) per rank, clipped, then sum w c rescaled to
  // sum w.
  void correct(const Observation& obs, const std::vector<double>& w) {
    const int P = obs.ranks(), S = obs.slices;
    for (int r = 0; r < P; ++r) {
      const int lo = r == 0 ? 0 : obs.boundaries[r - 1], hi = r + 1 < P ? obs.boundaries[r] : S;
      double predicted = 0;
      for (int s = lo; s < hi; ++s) predicted += w[s] * correction_[s];
      if (!(predicted > 0) || !(obs.times[r] > 0)) continue;
      const double gap = std::log(obs.times[r] / predicted);  // soft-thresholded: a gap within the noise floor is noise
      const double beyond = std::copysign(std::max(std::fabs(gap) - p_.noise_floor, 0.0), gap);
      if (beyond == 0) continue;
      const double f = std::exp(p_.gain * beyond);
      for (int s = lo; s < hi; ++s) correction_[s] = std::clamp(correction_[s] * f, kMinCorrection, kMaxCorrection);
    }
    double weighted = 0, total = 0;
    for (int s = 0; s < S; ++s) weighted += w[s] * correction_[s], total += w[s];
    if (weighted > 0 && total > 0)
      for (double& c : correction_) c = std::clamp(c * total / weighted, kMinCorrection, kMaxCorrection);
  }

  RepartitionParams p_;
  std::vector<double> correction_, previous_;
};

// weights: a file (default: the shipped one), or "none" for all-zero parameters (the base rule); each parameter given
// overrides the file's value.
const Registrar<PolicyInfo> registrar("learned_repartition",
                                      {[](PolicyParams& params) {
                                         const std::string file = params.text("weights", "");
                                         RepartitionParams p;
                                         if (file != "none")
                                           p = load_repartition_weights(resolve_repartition_weights(file));
                                         for (const auto& d : repartition_params())
                                           p.*d.field = params.real(d.name, p.*d.field, d.min, d.max);
                                         return make_learned_repartition(p);
                                       },
                                       PolicyNeeds{.slice_work = true}});

}  // namespace

const std::array<RepartitionParam, 6>& repartition_params() {
  static const std::array<RepartitionParam, 6> params{{{"gain", &RepartitionParams::gain, 0, 1},
                                                       {"noise_floor", &RepartitionParams::noise_floor, 0, 1},
                                                       {"trend", &RepartitionParams::trend, 0, 2},
                                                       {"deadband", &RepartitionParams::deadband, 0, 1},
                                                       {"move_cost", &RepartitionParams::move_cost, 0, 10},
                                                       {"fixed_cost", &RepartitionParams::fixed_cost, 0, 1}}};
  return params;
}

std::unique_ptr<Policy> make_learned_repartition(const RepartitionParams& p) {
  return std::make_unique<LearnedRepartitionPolicy>(p);
}

RepartitionParams load_repartition_weights(const std::string& path) {
  const auto f = h5::File::open_read(path);
  if (const auto got = f.read_text_attr("format"); got != "semlb-learned-repartition")
    throw InputError(path + ": attribute 'format' is '" + got + "', expected 'semlb-learned-repartition'");
  if (const long v = f.read_int_attr("version"); v != kRepartitionFormatVersion)
    throw InputError(path + ": attribute 'version' is " + std::to_string(v) + ", this build reads version " +
                     std::to_string(kRepartitionFormatVersion));
  RepartitionParams p;
  for (const auto& d : repartition_params()) {
    const double v = f.read_real_attr(d.name);
    if (!(v >= d.min && v <= d.max))
      throw InputError(path + ": attribute '" + d.name + "' = " + format_real(v) + " is outside [" +
                       format_real(d.min) + ", " + format_real(d.max) + "]");
    p.*d.field = v;
  }
  return p;
}

void save_repartition_weights(const std::string& path, const RepartitionParams& p,
                              const std::map<std::string, std::string>& meta) {
  h5::File::write_atomically(path, [&](h5::File& f) {
    f.write_attr("format", std::string("semlb-learned-repartition"));
    f.write_attr("version", kRepartitionFormatVersion);
    for (const auto& d : repartition_params()) f.write_attr(d.name, p.*d.field);
    for (const auto& [k, v] : meta) f.write_attr(k, v);
  });
}

std::string default_repartition_weights_path() {
  if (const char* env = std::getenv("SEMLB_REPARTITION_WEIGHTS")) return env;
  return (std::filesystem::path(SEMLB_DEFAULT_WEIGHTS).parent_path() / "learned_repartition" / "default.h5").string();
}

std::string resolve_repartition_weights(const std::string& path) {
  return resolve_weights_file(path, default_repartition_weights_path());
}

}  // namespace semlb
