// Surrogate smoke test of the production balancers: on evaluation seeds 9000-9004, P = 4, 100 events, the
// mean imbalance over the five seeds of gromacs_dlb, hoomd_balance, all_tensor and lammps_shift (weight=time)
// is below static's. Per seed it is not always (hoomd_balance on 9001 and 9003; all_tensor and lammps_shift
// never move on 9001), and lammps_shift on the biased slice-work proxy alone is worse than static, like
// persistence: docs/controllers.md "Production balancers".
#include <gtest/gtest.h>

#include <string>
#include <map>
#include <utility>

#include "controllers/policy.hpp"
#include "surrogate/rollout.hpp"
#include "surrogate/scenario.hpp"

using namespace semlb;

TEST(ProductionBalancersRollout, BeatStaticOnEvaluationSeeds) {
  const std::vector<std::pair<const char*, PolicyParams>> policies = {
      {"gromacs_dlb", {}},
      {"hoomd_balance", {}},
      {"all_tensor", {}},
      {"lammps_shift", PolicyParams(std::map<std::string, std::string>{{"weight", "time"}})}};
  double static_sum = 0.0;
  std::vector<double> sums(policies.size(), 0.0);
  std::vector<long> moved(policies.size(), 0);
  for (uint64_t seed = 9000; seed <= 9004; ++seed) {
    const auto scenario = surrogate::make_scenario(seed, 4);
    auto fixed = make_policy("static");
    static_sum += surrogate::rollout(scenario, *fixed, 100).mean_imbalance;
    for (size_t k = 0; k < policies.size(); ++k) {
      auto policy = make_policy(policies[k].first, policies[k].second);
      const auto r = surrogate::rollout(scenario, *policy, 100);
      sums[k] += r.mean_imbalance;
      moved[k] += r.migration;
    }
  }
  for (size_t k = 0; k < policies.size(); ++k) {
    EXPECT_LT(sums[k], static_sum) << policies[k].first;
    EXPECT_GT(moved[k], 0) << policies[k].first;  // it did rebalance
  }
}
