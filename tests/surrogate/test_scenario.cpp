// Scenarios: determinism, independence from ranks and policy, valid ranges, disjoint seed splits.
#include <gtest/gtest.h>

#include <cmath>

#include "common/errors.hpp"
#include "surrogate/scenario.hpp"

using namespace semlb::surrogate;

TEST(Scenario, SameSeedSameTrajectoryAndRanksDoNotChangeTheWorkload) {
  const Scenario a = make_scenario(9000, 4), b = make_scenario(9000, 4), c = make_scenario(9000, 16);
  Workload wa(a), wb(b), wc(c);
  for (int t = 0; t < 150; ++t) {
    ASSERT_EQ(wa.work(), wb.work());
    ASSERT_EQ(wa.work(), wc.work());
    ASSERT_EQ(measured_times(a, t, {1.0, 2.0}), measured_times(b, t, {1.0, 2.0}));
    wa.advance(), wb.advance(), wc.advance();
  }
  const Scenario d = make_scenario(9001, 4);
  EXPECT_NE(Workload(a).work(), Workload(d).work());
}

TEST(Scenario, RangesHoldForManySeeds) {
  int growth_events = 0;
  for (uint64_t seed = 0; seed < 60; ++seed) {
    for (int P : {1, 2, 16}) {
      const Scenario s = make_scenario(seed, P);
      ASSERT_GE(s.slices, 256);
      ASSERT_LE(s.slices, 1024);
      ASSERT_GE(s.min_width, 1);
      ASSERT_LE(2 * P * s.min_width, s.slices);
    }
    const Scenario s = make_scenario(seed, 8);
    Workload w(s);
    for (int t = 0; t < 100; ++t, w.advance()) {
      for (double x : w.work()) ASSERT_TRUE(std::isfinite(x) && x > 0.0);
      ASSERT_GE(w.growth_phase(), 0.0);
      ASSERT_LT(w.growth_phase(), 1.0);
      growth_events += w.growth_event();
      if (w.growth_event()) {
        ASSERT_EQ(w.growth_phase(), 0.0);
      }
    }
  }
  EXPECT_GT(growth_events, 60 * 100 / 31);
  EXPECT_THROW(make_scenario(1, 0), semlb::InputError);
  EXPECT_THROW(make_scenario(1, 5000), semlb::InputError);
}

TEST(Scenario, NoiseIsMultiplicativeAndNonNegative) {
  const Scenario s = make_scenario(3, 4);
  const std::vector<double> zero{0.0, 0.0};
  EXPECT_EQ(measured_times(s, 5, zero), zero);
  const auto w = Workload(s).work();
  const auto o = observed_work(s, 0, w);
  double rel = 0;
  for (size_t i = 0; i < w.size(); ++i) {
    ASSERT_GE(o[i], 0.0);
    rel = std::max(rel, std::fabs(o[i] / w[i] - 1.0));
  }
  EXPECT_GT(rel, 0.01);  // noisy
  EXPECT_LT(rel, 3.0);   // but bounded (3-sigma clip times the bias)
}

TEST(Scenario, SeedRangesAreDisjoint) {
  EXPECT_LT(kTrainSeeds.last, kValidationSeeds.first);
  EXPECT_LT(kValidationSeeds.last, kEvaluationSeeds.first);
  EXPECT_TRUE(kEvaluationSeeds.contains(9000) && kEvaluationSeeds.contains(9019));
}
