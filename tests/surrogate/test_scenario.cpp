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

TEST(Scenario, OverridesReplaceOnlyTheirDrawAndDependentDrawsFollow) {
  const Scenario a = make_scenario(9004, 4);
  // An override equal to nothing else changes nothing else: same hotspots, texture, bias, noise levels.
  const Scenario b = make_scenario(9004, 4, {{"time_jitter", "0.3"}, {"burst_size", "2"}});
  EXPECT_EQ(b.time_jitter, 0.3);
  EXPECT_EQ(b.burst_size, 2.0);
  EXPECT_EQ(b.work_noise, a.work_noise);
  EXPECT_EQ(b.texture, a.texture);
  ASSERT_EQ(b.hotspots.size(), a.hotspots.size());
  for (size_t h = 0; h < a.hotspots.size(); ++h) EXPECT_EQ(b.hotspots[h].velocity, a.hotspots[h].velocity);
  // slices sizes the texture; drift_speed scales the initial velocities (within the cap); min_width is kept.
  const Scenario c =
      make_scenario(9004, 4, {{"slices", "73"}, {"min_width", "13"}, {"drift_speed", "0.0004"}, {"drift_max", "1"}});
  EXPECT_EQ(c.slices, 73);
  EXPECT_EQ(c.texture.size(), 73u);
  EXPECT_EQ(c.min_width, 13);
  for (size_t h = 0; h < a.hotspots.size(); ++h)
    if (std::fabs(a.hotspots[h].velocity) < a.drift_max)
      EXPECT_DOUBLE_EQ(c.hotspots[h].velocity, 2.0 * a.hotspots[h].velocity);
  EXPECT_EQ(Workload(c).work().size(), 73u);
  // Faster drift changes the workload more: growth and bursts off, L1 change of the work over 50 events.
  const ScenarioSet still = {{"burst_probability", "0"}, {"growth_rate", "0"}, {"growth_period", "100000"}};
  ScenarioSet quick = still;
  quick.insert({{"drift_speed", "0.002"}, {"drift_walk", "0.0003"}, {"drift_max", "0.005"}});
  const Scenario slow = make_scenario(9004, 4, still), fast = make_scenario(9004, 4, quick);
  Workload ws(slow), wf(fast);
  const auto s0 = ws.work(), f0 = wf.work();
  for (int t = 0; t < 50; ++t) ws.advance(), wf.advance();
  double ds = 0, df = 0;
  for (size_t i = 0; i < s0.size(); ++i) ds += std::fabs(ws.work()[i] - s0[i]), df += std::fabs(wf.work()[i] - f0[i]);
  EXPECT_GT(df, 3 * ds);
}

TEST(Scenario, BadOverridesAreInputErrorsNamingTheKey) {
  auto message = [](const ScenarioSet& set) {
    try {
      make_scenario(9000, 4, set);
    } catch (const semlb::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({{"drift", "1"}}).rfind("scenario.drift: unknown scenario key (one of slices, ", 0), 0u);
  EXPECT_NE(message({{"work_noise", "0.1x"}}).find("scenario.work_noise: '0.1x' is not a number"), std::string::npos);
  EXPECT_NE(message({{"time_jitter", "2"}}).find("scenario.time_jitter: "), std::string::npos);
  EXPECT_NE(message({{"slices", "2.5"}}).find("scenario.slices: "), std::string::npos);
  EXPECT_NE(message({{"slices", "8"}, {"min_width", "3"}}).find("scenario.min_width: "),
            std::string::npos);  // 4 * 3 > 8
  EXPECT_NE(message({{"growth_period", "10"}, {"growth_offset", "10"}}).find("scenario.growth_offset: "),
            std::string::npos);
  EXPECT_EQ(message({{"slices", "8"}, {"min_width", "2"}}), "no error");
}

// The moving front (never drawn, only by override): the work behind it grows as it advances, ahead of it nothing
// changes, and without it the scenario is what the seed draws.
TEST(Scenario, AProliferativeFrontRaisesTheWorkBehindItAsItMoves) {
  const ScenarioSet still = {{"burst_probability", "0"},
                             {"growth_rate", "0"},
                             {"growth_period", "100000"},
                             {"drift_speed", "0"},
                             {"drift_walk", "0"}};
  ScenarioSet front = still;
  front.insert({{"front_amplitude", "2"}, {"front_speed", "0.01"}, {"front_start", "0.1"}});
  const Scenario base = make_scenario(9010, 4, still), f = make_scenario(9010, 4, front);
  EXPECT_EQ(f.texture, base.texture);
  Workload wb(base), wf(f);
  for (int t = 0; t < 40; ++t) wb.advance(), wf.advance();  // the front is at 0.1 + 0.4 = 0.5
  const int n = f.slices;
  auto at = [&](const Workload& w, double x) { return w.work()[static_cast<int>(x * n)]; };
  EXPECT_NEAR(at(wf, 0.2) - at(wb, 0.2), 2.0 * f.texture[static_cast<int>(0.2 * n)] / n,
              1e-12);  // 0.3 behind: the full ramp
  EXPECT_NEAR(at(wf, 0.4) - at(wb, 0.4), 1.0 * f.texture[static_cast<int>(0.4 * n)] / n,
              0.02 * 2.0 / n);          // 0.1 behind: half
  EXPECT_EQ(at(wf, 0.7), at(wb, 0.7));  // ahead of the front
  EXPECT_THROW(make_scenario(9010, 4, {{"front_amplitude", "-1"}}), semlb::InputError);
}
