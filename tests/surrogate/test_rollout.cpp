// Hard rollouts: metrics, determinism, static/oracle properties, zero-head GRU == reactive.
#include <gtest/gtest.h>

#include "../run_command.hpp"

#include <filesystem>

#include "common/errors.hpp"
#include "controllers/features.hpp"
#include "controllers/gru.hpp"
#include "controllers/metrics.hpp"
#include "controllers/partition.hpp"
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

// Per event: the oracle's partition of interval t is the min-max partition of the true W_t, and every
// policy's T_mean is the same (sum W_t / P), so no policy (gru with the shipped weights included) has a
// smaller (T_max - T_mean)/T_mean at any event. Event 0 is the shared initial partition.
TEST(Rollout, OracleIsTheFloorOfMaxOverMean) {
  const int events = 100;
  for (uint64_t seed : {9000, 9001, 9002}) {
    for (int P : {2, 4, 8, 16}) {
      const Scenario s = make_scenario(seed, P);
      auto per_event = [&](const char* name) {  // max/mean of each event's true times, from the trace
        auto p = make_policy(name);
        const auto r = rollout(s, *p, events, true);
        Workload w(s);
        std::vector<double> out;
        for (int t = 0; t < events; ++t, w.advance())
          out.push_back(max_over_mean(rank_sums(w.work(), r.trace[t].obs.boundaries)));
        double sum = 0;
        for (double v : out) sum += v;
        EXPECT_NEAR(sum / events, r.mean_max_over_mean, 1e-12) << name;  // the trace is the rollout's partition
        return out;
      };
      const auto floor = per_event("oracle");
      for (const char* name : {"static", "reactive", "persistence", "holt", "gru"}) {
        const auto other = per_event(name);
        EXPECT_EQ(other[0], floor[0]) << name;
        for (int t = 1; t < events; ++t)
          ASSERT_LE(floor[t], other[t] + 1e-12 * (1 + other[t]))
              << name << " seed " << seed << " P " << P << " event " << t;
      }
    }
  }
}

TEST(Rollout, ZeroHeadGruEqualsReactiveOn400EventRollouts) {
  const auto path = semlb::test::fresh_dir("rollout_zero") + "/zero.h5";
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
