// Hard rollouts: metrics, determinism, static/oracle properties, zero-head GRU == reactive.
#include <gtest/gtest.h>

#include <filesystem>

#include "controllers/errors.hpp"
#include "controllers/features.hpp"
#include "controllers/gru.hpp"
#include "controllers/metrics.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/rollout.hpp"

using namespace semlb;
using namespace semlb::surrogate;

TEST(Metrics, GlobalImbalanceAndMaxOverMean) {
  const std::vector<double> t{1.0, 2.0, 3.0};
  EXPECT_DOUBLE_EQ(global_imbalance(t), 1.0);
  EXPECT_DOUBLE_EQ(max_over_mean(t), 0.5);
  const std::vector<double> zero{0.0, 0.0};
  EXPECT_EQ(global_imbalance(zero), 0.0);
  EXPECT_EQ(max_over_mean(zero), 0.0);
}

TEST(Rollout, StaticNeverMigratesAndRolloutsAreDeterministic) {
  const Scenario s = make_scenario(9003, 8);
  auto a = make_policy("static"), b = make_policy("reactive"), c = make_policy("reactive");
  const auto ra = rollout(s, *a, 100);
  EXPECT_EQ(ra.migration, 0);
  const auto rb = rollout(s, *b, 100), rc = rollout(s, *c, 100);
  EXPECT_EQ(rb.imbalance, rc.imbalance);
  EXPECT_EQ(rb.migration, rc.migration);
  EXPECT_GT(rb.migration, 0);
  EXPECT_EQ(ra.imbalance.front(), rb.imbalance.front());  // same initial partition
  EXPECT_THROW(rollout(s, *a, 0), InputError);
}

TEST(Rollout, OracleIsTheFloorOfMaxOverMean) {
  for (uint64_t seed : {9000, 9001, 9002}) {
    for (int P : {2, 8}) {
      const Scenario s = make_scenario(seed, P);
      auto oracle = make_policy("oracle");
      const double floor = rollout(s, *oracle, 60).mean_max_over_mean;
      for (const char* name : {"static", "reactive", "persistence", "holt"}) {
        auto p = make_policy(name);
        EXPECT_LE(floor, rollout(s, *p, 60).mean_max_over_mean + 1e-12) << name << " seed " << seed << " P " << P;
      }
    }
  }
}

TEST(Rollout, ZeroHeadGruEqualsReactiveOn400EventRollouts) {
  const auto path = (std::filesystem::temp_directory_path() / "semlb_rollout_zero.h5").string();
  save_gru_weights(path, GruWeights::random_zero_head(24, kFeatureCount, 17));
  PolicyParams params;
  params.set("weights", path);
  for (int P : {2, 4, 16}) {
    const Scenario s = make_scenario(9010, P);
    auto gru = make_policy("gru", params);
    auto reactive = make_policy("reactive");
    const auto rg = rollout(s, *gru, 400, true), rr = rollout(s, *reactive, 400, true);
    ASSERT_EQ(rg.migration, rr.migration);
    for (int t = 0; t < 400; ++t) ASSERT_EQ(*rg.trace[t].decision, *rr.trace[t].decision) << "P " << P << " t " << t;
  }
  std::filesystem::remove(path);
}

TEST(Rollout, LongHorizonStaysFinite) {
  const Scenario s = make_scenario(9999, 16);
  auto reactive = make_policy("reactive");
  const auto r = rollout(s, *reactive, 2000);
  for (double v : r.imbalance) ASSERT_TRUE(std::isfinite(v));
  EXPECT_EQ(r.imbalance.size(), 2000u);
}

TEST(Evaluate, IntListsAndPolicyParams) {
  EXPECT_EQ(parse_int_list("9000-9002,7", "--seeds"), (std::vector<long>{9000, 9001, 9002, 7}));
  EXPECT_THROW(parse_int_list("9002-9000", "--seeds"), InputError);
  EXPECT_THROW(parse_int_list("9x", "--seeds"), InputError);
  EXPECT_THROW(parse_int_list("", "--seeds"), InputError);
  EXPECT_THROW(parse_int_list("-3", "--ranks"), InputError);
  const auto p = parse_policy_params({"holt.alpha=0.3", "gru.weights=a=b.h5"});
  EXPECT_TRUE(p.at("holt").has("alpha"));
  EXPECT_EQ(PolicyParams(p.at("gru")).text("weights", ""), "a=b.h5");
  EXPECT_THROW(parse_policy_params({"alpha=0.3"}), InputError);
}
