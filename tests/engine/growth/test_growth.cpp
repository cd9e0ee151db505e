// Every registered growth law on every backend this machine runs, in both precisions: each cell adds the elements its
// evaluator gives and keeps the field it writes, the backend's new state is the host reference's (cells.cpp), and a
// scene names the law as effects.growth.law. Then clock by hand and the growth section's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/physics/cpu_physics.hpp"
#include "engine/growth/growth_law.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

TEST(GrowthLaws, EveryLawOnEveryBackendGrowsWhatItsEvaluatorGives) {
  ASSERT_FALSE(GrowthLaws::names().empty());
  for (const auto& name : GrowthLaws::names()) {
    const GrowthLaw& law = GrowthLaws::at(name);
    State s = testing::random_state(60, 8, 24.0, 31);
    const CellRules rules = testing::rules_of("  growth: " + law.example + "\n", s);
    ASSERT_EQ(GrowthLaws::names().at(rules.growth), name) << "the scene's law is the one the rules call";
    for (const auto& [backend, precision] : testing::backend_precisions()) {
      CellRules r = rules;
      r.single = precision == "float";
      auto b = testing::backend(backend, precision);
      b->upload(s);
      State host = s;
      b->download(host);  // the positions as this backend holds them (float: rounded)
      long born = 0;
      for (int stage = 1; stage <= 3; ++stage) {
        cellrules::semlb_cell_stage_at(&r, 2.0 * stage);
        State want = host;  // the host reference of this stage on the same state
        run_cell_stage(want, r, 7, 1.0, 10 * stage);
        std::vector<double>* field = law.field.empty() ? nullptr : &host.cell_fields.at(law.field);
        std::vector<int> counts(host.cell_count);
        std::vector<double> fields = field ? *field : std::vector<double>{};
        for (long c = 0; c < host.cells(); ++c) {  // what the evaluator gives each cell
          const auto ctr = centroid(host, c);
          double f = field ? fields[c] : 0.0;
          counts[c] += law.births(host.cell_type[c], host.cell_count[c], ctr.data(), r.time, 1.0, r.growth_p, &f);
          if (field) fields[c] = f;
        }
        b->update_cells(host, r, 7, 1.0, 10 * stage);
        b->download(host);
        const std::string at = name + " on " + backend + " " + precision + ", stage " + std::to_string(stage);
        ASSERT_EQ(host.cell_count, counts) << at;
        if (field) {
          EXPECT_EQ(host.cell_fields.at(law.field), fields) << at;
        }
        EXPECT_EQ(host.cell_id, want.cell_id) << at;
        EXPECT_EQ(host.cell_fields, want.cell_fields) << at;
        ASSERT_EQ(host.position.size(), want.position.size()) << at;
        double worst = 0;  // the newborns' draws (log, cos) may differ by ulps between the host and a device
        for (size_t i = 0; i < host.position.size(); ++i)
          worst = std::max(worst, std::abs(host.position[i] - want.position[i]));
        EXPECT_LT(worst, precision == "double" ? 1e-9 : 1e-5) << at;
        born = host.elements() - s.elements();
      }
      EXPECT_GT(born, 0) << name << ": the example grows nothing on " << backend;
    }
  }
}

// clock.h by hand (its C++ instantiation, as registered): p = (period 2 h, basal only, max 20, front, x0, speed,
// cycle).
TEST(GrowthLaws, ClockFollowsTheClockStopsAtTheMaximumAndWaitsForTheFront) {
  const GrowthEvaluator clock_law = GrowthLaws::at("clock").births;
  const double p[7] = {2, 1, 20, 0, 0, 0, 20}, centre[3] = {20, 0, 0};
  double clock = 1.5;
  EXPECT_EQ(clock_law(0, 10, centre, 0, 5.0, p, &clock), 3);  // 6.5 h: three periods, 0.5 h left
  EXPECT_EQ(clock, 0.5);
  clock = 1.5;
  EXPECT_EQ(clock_law(0, 19, centre, 0, 5.0, p, &clock), 1);  // a full cell waits; its clock wraps
  EXPECT_EQ(clock, 0.5);
  clock = 1.5;
  EXPECT_EQ(clock_law(1, 10, centre, 0, 5.0, p, &clock), 0);  // spinous cells do not grow
  EXPECT_EQ(clock, 1.5);
  const double front[7] = {2, 1, 20, 1, 0, 2, 20};  // a front at 2 t um
  clock = 1.5;
  EXPECT_EQ(clock_law(0, 10, centre, 9.0, 5.0, front, &clock), 0);  // at 18 um: ahead, clock stands
  EXPECT_EQ(clock, 1.5);
  EXPECT_EQ(clock_law(0, 10, centre, 10.0, 5.0, front, &clock), 3);  // at 20 um: behind (<=) counts
}

// A huge but finite clock (an edited state, a checkpoint of a slow cycle restarted with a fast one) takes closed-form
// time: births capped by the room left, the clock reduced modulo the period; below 64 periods the loop's own bits.
TEST(GrowthLaws, ClockOfAnyMagnitudeEndsInBoundedTime) {
  const GrowthEvaluator clock_law = GrowthLaws::at("clock").births;
  const double p[7] = {2, 1, 20, 0, 0, 0, 20}, centre[3] = {20, 0, 0};
  double clock = 1e300;  // 1e300 - 2 == 1e300: a loop that subtracts the period never ends
  EXPECT_EQ(clock_law(0, 10, centre, 0, 5.0, p, &clock), 10);
  EXPECT_GE(clock, 0.0);
  EXPECT_LT(clock, 2.0);
  EXPECT_EQ(clock, std::fmod(1e300 + 5.0, 2.0));
  clock = 3.6e13;  // 1e10 h as a 1e12-h cycle's clock: 1.8e13 periods of 2 h
  EXPECT_EQ(clock_law(0, 19, centre, 0, 5.0, p, &clock), 1);
  EXPECT_EQ(clock, std::fmod(3.6e13 + 5.0, 2.0));
  clock = 200.0;  // 102.5 periods: more than the room (10), the clock wraps
  EXPECT_EQ(clock_law(0, 10, centre, 0, 5.0, p, &clock), 10);
  EXPECT_EQ(clock, 1.0);
  clock = 1.7976931348623157e308;  // the largest double: + 5 h stays finite
  EXPECT_EQ(clock_law(0, 0, centre, 0, 5.0, p, &clock), 20);
  EXPECT_LT(clock, 2.0);
  // Below 64 periods, the loop: exactly what subtracting 2 h at a time gives.
  for (double c0 : {0.1, 7.3, 33.3, 120.9, 122.9}) {
    double ref_clock = c0 + 5.0;
    int ref = 0;
    for (; ref_clock >= 2.0; ref_clock -= 2.0)
      if (10 + ref < 20) ++ref;
    clock = c0;
    EXPECT_EQ(clock_law(0, 10, centre, 0, 5.0, p, &clock), ref) << c0;
    EXPECT_EQ(clock, ref_clock) << c0;
  }
}

TEST(GrowthLaws, GrowthSettingsAreChecked) {
  testing::expect_errors_name_fields(
      {{"effects.growth={law: nope}", "effects.growth.law"},
       {"effects.growth={law: clock, offset: -1}", "effects.growth.offset"},
       {"effects.growth={cycle_time: 0}", "effects.growth.cycle_time"},
       {"effects.growth={min_elements: 12, max_elements: 12}", "effects.growth.max_elements"},
       {"effects.growth={rule: clock}", "effects.growth.rule"}});
}

}  // namespace
}  // namespace semlb::engine
