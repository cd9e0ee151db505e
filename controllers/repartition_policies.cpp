// Repartitioning policies: persistence and holt (forecast, then optimal partition) and the oracle.
#include <memory>

#include "chains.hpp"
#include "errors.hpp"
#include "forecast.hpp"
#include "policy.hpp"

namespace semlb {
namespace {

const std::vector<double>& require(const std::vector<double>& v, const Observation& obs, const char* policy,
                                   const char* field) {
  if (v.empty())
    throw InputError("event " + std::to_string(obs.event) + ": policy '" + policy + "' needs " + field +
                     " in the observation");
  return v;
}

class PersistencePolicy final : public Policy {
 public:
  std::vector<int> decide(const Observation& obs) override {
    return optimal_partition(require(obs.slice_work, obs, "persistence", "slice_work"), obs.ranks(),
                             obs.min_width);
  }
};

class HoltPolicy final : public Policy {
 public:
  HoltPolicy(double alpha, double beta) : holt_(alpha, beta) {}
  std::vector<int> decide(const Observation& obs) override {
    const auto forecast = holt_.update(require(obs.slice_work, obs, "holt", "slice_work"));
    return optimal_partition(forecast, obs.ranks(), obs.min_width);
  }

 private:
  HoltForecaster holt_;
};

class OraclePolicy final : public Policy {
 public:
  std::vector<int> decide(const Observation& obs) override {
    return optimal_partition(require(obs.oracle_work, obs, "oracle", "oracle_work"), obs.ranks(),
                             obs.min_width);
  }
};

const Registrar persistence_registrar("persistence",
                                      [](PolicyParams&) { return std::make_unique<PersistencePolicy>(); });
// Defaults chosen on training seeds only (experiments/holt_tuning.yaml; docs/controllers.md).
const Registrar holt_registrar("holt", [](PolicyParams& p) {
  return std::make_unique<HoltPolicy>(p.real("alpha", 0.2), p.real("beta", 0.0));
});
const Registrar oracle_registrar("oracle", [](PolicyParams&) { return std::make_unique<OraclePolicy>(); });

}  // namespace
}  // namespace semlb
