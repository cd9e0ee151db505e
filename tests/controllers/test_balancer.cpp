// Balancer: the one rebalancing event (observe, decide, check, count) and its checkpointed state.
#include <gtest/gtest.h>

#include <stdexcept>

#include "controllers/balancer.hpp"
#include "common/errors.hpp"
#include "controllers/gru.hpp"
#include "controllers/partition.hpp"
#include "surrogate/scenario.hpp"

using namespace semlb;

namespace {

// A moving workload (the surrogate's) measured under the balancer's current boundaries.
struct Episode {
  explicit Episode(int ranks) : scenario(surrogate::make_scenario(9001, ranks)), workload(scenario) {}
  Measurement next(const Balancer& b) {
    const int t = workload.event();
    Measurement m;
    m.times = surrogate::measured_times(scenario, t, rank_sums(workload.work(), b.boundaries()));
    m.slice_work = surrogate::observed_work(scenario, t, workload.work());
    m.growth_phase = workload.growth_phase();
    m.growth_event = workload.growth_event();
    workload.advance();
    m.true_work = workload.work();
    return m;
  }
  surrogate::Scenario scenario;
  surrogate::Workload workload;
};

Balancer make(const std::string& policy, const Episode& run) {
  PolicyParams p;
  if (policy == "gru") p.set("weights", default_gru_weights_path());
  return Balancer(policy, make_policy(policy, p), run.scenario.slices, run.scenario.min_width,
                  uniform_partition(run.scenario.ranks, run.scenario.slices));
}

class WrongPolicy final : public Policy {
 public:
  std::vector<int> decide(const Observation& obs) override { return {obs.slices + 5}; }
};

}  // namespace

TEST(Balancer, CountsMigrationEventsAndWritesTheTrace) {
  Episode run(4);
  Balancer b = make("reactive", run);
  long moved = 0;
  for (int t = 0; t < 20; ++t) {
    const auto before = b.boundaries();
    const auto d = b.rebalance(run.next(b));
    EXPECT_EQ(d.trace.obs.event, t);
    EXPECT_EQ(d.trace.obs.boundaries, before);
    ASSERT_TRUE(d.trace.decision);
    EXPECT_EQ(*d.trace.decision, d.boundaries);
    EXPECT_EQ(d.boundaries, b.boundaries());
    EXPECT_EQ(d.moved, migration(before, d.boundaries));
    moved += d.moved;
  }
  EXPECT_EQ(b.event(), 20);
  EXPECT_EQ(b.migration(), moved);
  EXPECT_GT(moved, 0);  // the workload moves, so reactive does too
}

TEST(Balancer, RefusesAnInvalidMeasurementAndAnInvalidDecision) {
  WrongPolicy wrong;
  Balancer b("wrong", wrong, 100, 4, {50});
  Measurement bad;
  bad.times = {1.0, 2.0, 3.0};  // three times for two ranks
  EXPECT_THROW(b.observe(bad), InputError);
  Measurement m;
  m.times = {1.0, 2.0};
  try {
    b.rebalance(m);
    FAIL() << "an out-of-range boundary was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("event 0: policy 'wrong' returned an invalid partition"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(b.boundaries(), std::vector<int>{50});  // nothing was applied
  EXPECT_EQ(b.event(), 0);
  EXPECT_THROW(Balancer("static", make_policy("static"), 100, 4, {2}), InputError);  // initial partition too narrow
}

TEST(Balancer, PoliciesDeclareWhatTheyNeed) {
  EXPECT_TRUE(policy_needs("oracle").true_work);
  EXPECT_TRUE(policy_needs("lazy_oracle").true_work);
  EXPECT_TRUE(policy_needs("holt").slice_work);
  EXPECT_TRUE(policy_needs("persistence").slice_work);
  EXPECT_FALSE(policy_needs("reactive").slice_work || policy_needs("reactive").true_work);
  EXPECT_FALSE(policy_needs("gru").true_work);
  EXPECT_TRUE(policy_needs("learned_repartition").slice_work);
  EXPECT_THROW(policy_needs("nope"), InputError);
}

// A balancer restored from a saved state decides exactly like the one that kept running; a fresh one
// (the state ignored) does not, so the state is what carries the history.
class BalancerRestart : public ::testing::TestWithParam<std::string> {};

TEST_P(BalancerRestart, ARestoredBalancerContinuesIdentically) {
  const std::string policy = GetParam();
  Episode a(8), b(8), c(8);
  Balancer whole = make(policy, a), first = make(policy, b);
  for (int t = 0; t < 30; ++t) {
    whole.rebalance(a.next(whole));
    first.rebalance(b.next(first));
    c.next(first);  // keeps c's workload at the same event
  }
  const BalancerState saved = first.save_state();
  EXPECT_EQ(saved.event, 30);
  EXPECT_FALSE(saved.policy.empty());
  Balancer resumed = make(policy, c), fresh = make(policy, c);
  resumed.load_state(saved);
  fresh.load_state({saved.event, saved.migration, saved.boundaries, {}});  // same partition, no policy history
  Episode d = c;
  bool fresh_differs = false;
  for (int t = 30; t < 60; ++t) {
    const auto m = a.next(whole);
    const auto expected = whole.rebalance(m);
    const auto got = resumed.rebalance(c.next(resumed));
    ASSERT_EQ(got.boundaries, expected.boundaries) << policy << " at event " << t;
    ASSERT_EQ(got.trace.obs.event, t);
    fresh_differs = fresh_differs || fresh.rebalance(d.next(fresh)).boundaries != expected.boundaries;
  }
  EXPECT_EQ(resumed.migration(), whole.migration());
  EXPECT_TRUE(fresh_differs)
      << policy << ": a balancer without the saved history decided the same; the test would not see a lost state";
}

INSTANTIATE_TEST_SUITE_P(Policies, BalancerRestart, ::testing::Values("holt", "gru", "learned_repartition"));

TEST(Balancer, RefusesAStateOfAnotherRankCount) {
  Episode run(4);
  Balancer b = make("holt", run);
  BalancerState s = b.save_state();
  s.boundaries.push_back(run.scenario.slices - 1);
  EXPECT_THROW(b.load_state(s), InputError);
  s = b.save_state();
  s.policy["bogus"] = {1.0};
  EXPECT_THROW(b.load_state(s), InputError);
  // gru: the hidden states must match the tracked boundaries (H x B), the tracked boundaries be slice indices.
  Balancer g = make("gru", run);
  for (int t = 0; t < 3; ++t) g.rebalance(run.next(g));
  const BalancerState good = g.save_state();
  EXPECT_NO_THROW(g.load_state(good));
  s = good;
  s.policy["hidden"].push_back(0.0);
  EXPECT_THROW(g.load_state(s), InputError);
  s = good;
  s.policy["tracker.prev_boundaries"][0] += 0.5;
  EXPECT_THROW(g.load_state(s), InputError);
}
