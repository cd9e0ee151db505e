// Repartitioning policies: persistence and holt (forecast, then optimal partition), the oracle and the lazy oracle.
#include <memory>

#include "chains.hpp"
#include "common/errors.hpp"
#include "forecast.hpp"
#include "metrics.hpp"
#include "partition.hpp"
#include "policy.hpp"

namespace semlb {
namespace {

// cut=optimal: the exact minimum-bottleneck partition of W_s (milliseconds at thousands of slices); cut=quantile: the
// equal-share cut from a prefix sum (microseconds), the base rule of learned_repartition.
class PersistencePolicy final : public Policy {
 public:
  explicit PersistencePolicy(bool quantile) : quantile_(quantile) {}
  std::vector<int> decide(const Observation& obs) override {
    const auto& work = require_field(obs.slice_work, obs, "persistence", "slice_work");
    if (quantile_)
      return apply_targets(obs.boundaries, equal_share_targets(work, obs.ranks()), obs.slices, obs.min_width);
    return optimal_partition(work, obs.ranks(), obs.min_width);
  }

 private:
  bool quantile_;
};

class HoltPolicy final : public Policy {
 public:
  HoltPolicy(double alpha, double beta) : holt_(alpha, beta) {}
  std::vector<int> decide(const Observation& obs) override {
    const auto forecast = holt_.update(require_field(obs.slice_work, obs, "holt", "slice_work"));
    return optimal_partition(forecast, obs.ranks(), obs.min_width);
  }
  PolicyState save_state() const override { return {{"level", holt_.level()}, {"trend", holt_.trend()}}; }
  void load_state(const PolicyState& s) override {  // empty: no history yet
    if (s.empty()) return holt_.restore({}, {});
    if (s.size() != 2 || !s.count("level") || !s.count("trend"))
      throw InputError("holt state: expected level and trend");
    holt_.restore(s.at("level"), s.at("trend"));
  }

 private:
  HoltForecaster holt_;
};

class OraclePolicy final : public Policy {
 public:
  std::vector<int> decide(const Observation& obs) override {
    return optimal_partition(require_field(obs.oracle_work, obs, "oracle", "oracle_work"), obs.ranks(), obs.min_width);
  }
};

// Knows the next interval's true work, keeps the boundaries while their imbalance on it is at most tau,
// and otherwise moves to the nearest partition whose bottleneck is within (1 + slack) of the optimum: what
// perfect foresight buys per migrated slice (docs/controllers.md).
class LazyOraclePolicy final : public Policy {
 public:
  LazyOraclePolicy(double tau, double slack) : tau_(tau), slack_(slack) {}
  std::vector<int> decide(const Observation& obs) override {
    const auto& work = require_field(obs.oracle_work, obs, "lazy_oracle", "oracle_work");
    if (global_imbalance(rank_sums(work, obs.boundaries)) <= tau_) return obs.boundaries;
    const double best = bottleneck(work, optimal_partition(work, obs.ranks(), obs.min_width));
    return nearest_partition(work, obs.boundaries, obs.min_width, best * (1.0 + slack_));
  }

 private:
  double tau_, slack_;
};

constexpr PolicyNeeds kSliceWork{.slice_work = true};
constexpr PolicyNeeds kTrueWork{.true_work = true};

const Registrar<PolicyInfo> persistence_registrar(
    "persistence", {[](PolicyParams& p) {
                      const std::string cut = p.text("cut", "optimal");
                      if (cut != "optimal" && cut != "quantile")
                        throw InputError("policy parameter 'cut': must be optimal or quantile, got '" + cut + "'");
                      return std::make_unique<PersistencePolicy>(cut == "quantile");
                    },
                    kSliceWork});
// Defaults chosen on training seeds only (experiments/holt_tuning.yaml; docs/controllers.md).
const Registrar<PolicyInfo> holt_registrar("holt", {[](PolicyParams& p) {
                                                      return std::make_unique<HoltPolicy>(
                                                          p.real("alpha", 0.2, 0.0, 1.0, true),
                                                          p.real("beta", 0.0, 0.0, 1.0));
                                                    },
                                                    kSliceWork});
const Registrar<PolicyInfo> oracle_registrar("oracle", {[](PolicyParams&) { return std::make_unique<OraclePolicy>(); },
                                                        kTrueWork});
const Registrar<PolicyInfo> lazy_oracle_registrar("lazy_oracle", {[](PolicyParams& p) {
                                                                    return std::make_unique<LazyOraclePolicy>(
                                                                        p.real("tau", 0.1, 0.0, kMaxThreshold),
                                                                        p.real("slack", 0.0, 0.0, 10.0));
                                                                  },
                                                                  kTrueWork});

}  // namespace
}  // namespace semlb
