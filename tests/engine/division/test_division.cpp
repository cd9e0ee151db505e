// Every registered division rule on every backend this machine runs, in both precisions: the backend's new state is
// the host reference's (cells.cpp) bit for bit, and every daughter lies on the far side of the plane normal to the
// rule's axis; a scene names the rule as effects.division.rule. Then the two shipped rules on one elongated cell, and
// the division section's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/physics/cpu_physics.hpp"
#include "engine/division/division_rule.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

// The split axis rule `name` gives cell c of s (its gyration tensor as cells.h sums it).
std::array<double, 3> axis_of(const std::string& name, const State& s, long c, const double* p) {
  const auto ctr = centroid(s, c);
  double g[6] = {0, 0, 0, 0, 0, 0};
  for (int k = 0; k < s.cell_count[c]; ++k) {
    const double* x = &s.position[3 * (s.cell_first[c] + k)];
    const double d[3] = {x[0] - ctr[0], x[1] - ctr[1], x[2] - ctr[2]};
    const double terms[6] = {d[0] * d[0], d[0] * d[1], d[0] * d[2], d[1] * d[1], d[1] * d[2], d[2] * d[2]};
    for (int i = 0; i < 6; ++i) g[i] += terms[i] / s.cell_count[c];
  }
  std::array<double, 3> axis{};
  DivisionRules::at(name).axis(g, ctr.data(), p, axis.data());
  return axis;
}

TEST(DivisionRules, EveryRuleOnEveryBackendSplitsAsItsEvaluatorSays) {
  ASSERT_FALSE(DivisionRules::names().empty());
  for (const auto& name : DivisionRules::names()) {
    const DivisionRule& rule = DivisionRules::at(name);
    State s = testing::random_state(30, 16, 24.0, 11);  // 16 elements: above the examples' at_elements
    const CellRules rules = testing::rules_of("  division: " + rule.example + "\n", s);
    ASSERT_EQ(DivisionRules::names().at(rules.division), name);
    for (const auto& [backend, precision] : testing::backend_precisions()) {
      auto b = testing::backend(backend, precision);
      b->upload(s);
      State before = s;
      b->download(before);
      State want = before;
      ASSERT_TRUE(run_cell_stage(want, rules, 3, 0.1, 10));
      State host = before;
      EXPECT_TRUE(b->update_cells(host, rules, 3, 0.1, 10));
      b->download(host);
      const std::string at = name + " on " + backend + " " + precision;
      EXPECT_EQ(host.hash(), want.hash()) << at;
      EXPECT_EQ(host.cells(), before.cells() + std::count(before.cell_type.begin(), before.cell_type.end(), kBasal))
          << at;
      for (long c = 0; c < before.cells(); ++c) {  // every daughter beyond every stayer along the rule's axis
        if (before.cell_type[c] != kBasal) continue;
        const auto axis = axis_of(name, before, c, rules.division_p);
        const long d = std::find(host.cell_id.begin(), host.cell_id.end(), daughter_id(before.cell_id[c], 0)) -
                       host.cell_id.begin();
        ASSERT_LT(d, host.cells()) << at << ": cell " << c << " has no daughter";
        const auto ctr = centroid(before, c);
        double stay = -INFINITY, leave = INFINITY;
        for (int k = 0; k < host.cell_count[c]; ++k) {
          const double* x = &host.position[3 * (host.cell_first[c] + k)];
          stay = std::max(stay, (x[0] - ctr[0]) * axis[0] + (x[1] - ctr[1]) * axis[1] + (x[2] - ctr[2]) * axis[2]);
        }
        for (int k = 0; k < host.cell_count[d]; ++k) {
          const double* x = &host.position[3 * (host.cell_first[d] + k)];
          leave = std::min(leave, (x[0] - ctr[0]) * axis[0] + (x[1] - ctr[1]) * axis[1] + (x[2] - ctr[2]) * axis[2]);
        }
        EXPECT_LE(stay, leave) << at << ": cell " << c;
      }
    }
  }
}

// A cell whose lineage has divided kMaxDivisionDepth times has no id left for a daughter: every backend stops the
// cell stage naming the step, the cell, the limit and the way out, not an id that would collide.
TEST(DivisionRules, ALineageOutOfIdsStopsNamingStepCellAndLimit) {
  State s = testing::random_state(30, 16, 24.0, 11);
  const CellRules rules = testing::rules_of("  division: " + DivisionRules::at("long_axis").example + "\n", s);
  for (double& d : s.cell_fields.at("division.depth")) d = kMaxDivisionDepth;
  for (const auto& [backend, precision] : testing::backend_precisions()) {
    auto b = testing::backend(backend, precision);
    b->upload(s);
    State host = s;
    try {
      b->update_cells(host, rules, 3, 0.1, 10);
      ADD_FAILURE() << backend << " " << precision << ": no error";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("step 10: cell ", 0), 0u) << m;
      EXPECT_NE(m.find("would divide a 37th time, but a lineage has ids for 36 divisions"), std::string::npos) << m;
    }
  }
}

// One basal cell of 20 elements stretched along x (x in [0, 19] um, y and z within 1 um): long_axis cuts it across x,
// oriented with the normal z cuts it into a lower and an upper half whatever its shape.
TEST(DivisionRules, LongAxisFollowsTheShapeOrientedItsAxis) {
  State cell;
  cell.cell_id = {9};
  cell.cell_type = {kBasal};
  cell.cell_count = {20};
  for (int k = 0; k < 20; ++k)
    for (double v : {double(k), 0.4 * std::sin(1.7 * k), 0.5 * std::cos(2.3 * k) + 10}) cell.position.push_back(v);
  cell.reindex();
  for (const auto& [section, d] : {std::pair{"{rule: long_axis}", 0}, std::pair{"{rule: oriented, axis: [0, 0, 1]}", 2},
                                   std::pair{"{rule: oriented, axis: [0, -3, 0]}", 1}}) {
    State s = cell;
    const CellRules r = testing::rules_of(std::string("  division: ") + section + "\n", s);
    ASSERT_TRUE(run_cell_stage(s, r, 1, 0.1, 0)) << section;
    ASSERT_EQ(s.cells(), 2) << section;
    const double c = centroid(cell, 0)[d];
    const bool minus = std::string(section).find("-3") != std::string::npos;  // the normal -y: the daughter below
    for (int k = 0; k < s.cell_count[0]; ++k) {
      const double x = s.position[3 * (s.cell_first[0] + k) + d];
      EXPECT_TRUE(minus ? x >= c : x <= c) << section << ": mother element " << k;
    }
    for (int k = 0; k < s.cell_count[1]; ++k) {
      const double x = s.position[3 * (s.cell_first[1] + k) + d];
      EXPECT_TRUE(minus ? x < c : x > c) << section << ": daughter element " << k;
    }
    EXPECT_GT(s.cell_count[1], 0) << section;
  }
}

TEST(DivisionRules, DivisionSettingsAreChecked) {
  testing::expect_errors_name_fields(
      {{"effects.division={rule: nope}", "effects.division.rule"},
       {"effects.division={at_elements: 1}", "effects.division.at_elements"},
       {"effects.division={types: [stem]}", "effects.division.types"},
       {"effects.division={rule: oriented, axis: [0, 0, 0]}", "effects.division.axis"},
       {"effects.division={rule: oriented, axis: [1, 2]}", "effects.division.axis"},
       {"effects.division={rule: oriented, axis: [a, 0, 1]}", "effects.division.axis"},
       {"effects.division={rule: long_axis, axis: [0, 0, 1]}", "effects.division.axis"}});
}

}  // namespace
}  // namespace semlb::engine
