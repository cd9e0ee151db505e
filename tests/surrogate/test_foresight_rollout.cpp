// foresight_rollout on surrogate scenarios: huge lambda is static, lambda 0 at P = 2 is the one-step oracle,
// and the surrogate runner's CSV row for `foresight` comes from the offline solve.
#include <gtest/gtest.h>

#include "controllers/policy.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/rollout.hpp"

using namespace semlb;
using namespace semlb::surrogate;

TEST(ForesightRollout, HugeLambdaIsStaticAndZeroLambdaMatchesTheOracleAtTwoRanks) {
  const Scenario s = make_scenario(9001, 2);
  auto still = make_policy("static"), oracle = make_policy("oracle");
  const auto rs = rollout(s, *still, 40), ro = rollout(s, *oracle, 40);
  const auto frozen = foresight_rollout(s, 1e6, 40), free = foresight_rollout(s, 0.0, 40);
  EXPECT_EQ(frozen.migration, 0);
  EXPECT_EQ(frozen.imbalance, rs.imbalance);
  // At P = 2 the least bottleneck is the least |T1 - T2|: the oracle (which sees interval t's work at event
  // t-1) reaches the per-interval optimum, and so does foresight without a move cost.
  ASSERT_EQ(free.imbalance.size(), ro.imbalance.size());
  for (size_t t = 0; t < ro.imbalance.size(); ++t) EXPECT_NEAR(free.imbalance[t], ro.imbalance[t], 1e-12) << t;
  EXPECT_GT(free.migration, 0);
}

TEST(ForesightRollout, MigrationFallsAsLambdaGrows) {
  const Scenario s = make_scenario(9002, 2);  // exact at P = 2: migration cannot grow with lambda
  long previous = -1;
  double previous_imbalance = 0;
  for (double lambda : {1.0, 0.01, 0.001, 0.0}) {
    const auto r = foresight_rollout(s, lambda, 30);
    EXPECT_GE(r.migration, previous) << lambda;
    if (previous >= 0) {
      EXPECT_LE(r.mean_imbalance, previous_imbalance + 1e-12) << lambda;
    }
    previous = r.migration;
    previous_imbalance = r.mean_imbalance;
  }
}

TEST(ForesightRollout, EvalJobUsesTheOfflineSolve) {
  std::map<std::string, PolicyParams> params;
  params["foresight"].set("lambda", "0.002");
  const auto row = run_eval_job({"foresight", 2, 9000, 30}, params, false);
  const auto r = foresight_rollout(make_scenario(9000, 2), 0.002, 30);
  EXPECT_EQ(row[0], "foresight");
  EXPECT_EQ(row[7], std::to_string(r.migration));
  EXPECT_DOUBLE_EQ(std::stod(row[6]), r.mean_imbalance);
}
