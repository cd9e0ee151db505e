// Surrogate smoke test of the production balancers: on evaluation seeds 9000-9004, P = 4, 100 events, each
// of gromacs_dlb, hoomd_balance, all_tensor and lammps_shift ends with a lower mean imbalance than static.
#include <gtest/gtest.h>

#include "controllers/policy.hpp"
#include "surrogate/rollout.hpp"
#include "surrogate/scenario.hpp"

using namespace semlb;

TEST(ProductionBalancersRollout, BeatStaticOnEvaluationSeeds) {
  for (uint64_t seed = 9000; seed <= 9004; ++seed) {
    const auto scenario = surrogate::make_scenario(seed, 4);
    auto fixed = make_policy("static");
    const double static_imbalance = surrogate::rollout(scenario, *fixed, 100).mean_imbalance;
    for (const char* name : {"gromacs_dlb", "hoomd_balance", "all_tensor", "lammps_shift"}) {
      auto policy = make_policy(name);
      const auto r = surrogate::rollout(scenario, *policy, 100);
      EXPECT_LT(r.mean_imbalance, static_imbalance) << name << " seed " << seed;
      EXPECT_GT(r.migration, 0) << name << " seed " << seed;  // it did rebalance
    }
  }
}
