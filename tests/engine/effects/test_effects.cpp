// Invariants of the cell effects: growth adds elements at the stated rate, division conserves elements
// and splits across the long axis, differentiation follows its rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <set>
#include <thread>

#include "engine/effects/cell_fields.hpp"
#include "engine/effects/effect.hpp"
#include "engine/fates/fate.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

using testing::scene_from;

// One cell of `n` elements on a line along `axis` (spacing 1 um), at height z.
State line_cell(int n, int axis, double z, int type = kBasal) {
  State s;
  s.cell_id = {5};
  s.cell_type = {type};
  s.cell_count = {n};
  for (int k = 0; k < n; ++k) {
    double p[3] = {20, 20, z};
    p[axis] += k - (n - 1) / 2.0;
    s.position.insert(s.position.end(), p, p + 3);
  }
  s.reindex();
  return s;
}

using testing::rules_of;
// One cell stage of rules `r` on the host reference.
bool stage(State& s, const CellRules& r, double elapsed) { return run_cell_stage(s, r, 1, elapsed, s.step); }

TEST(Effects, GrowthAddsOneElementPerPeriodUpToTheMaximum) {
  State s = line_cell(10, 0, 5);
  const auto r = rules_of("  growth: {cycle_time: 20, min_elements: 10, max_elements: 20, offset: 1.0}\n", s);
  s.cell_fields["growth.clock"] = {0.0};
  for (int k = 1; k <= 15; ++k) {
    stage(s, r, 2.0);  // one period (20 h / 10 elements)
    ASSERT_EQ(s.cell_count[0], std::min(10 + k, 20))
        << "after " << k << " periods";  // one each, capped at max_elements
  }
  EXPECT_EQ(s.elements(), 20);
  for (long e = 10; e < 20; ++e)  // newborns sit at `offset` from the centroid at their birth
    EXPECT_LT(std::abs(s.position[3 * e + 2] - 5), 2.0);
}

TEST(Effects, GrowthSkipsTypesItIsNotFor) {
  State s = line_cell(10, 0, 5, kGranular);
  const auto r = rules_of("  growth: {cycle_time: 20}\n", s);
  EXPECT_FALSE(stage(s, r, 100.0));
  EXPECT_EQ(s.elements(), 10);
}

// The proliferative front (growth.front): a cell grows only while its centroid x <= x0 + speed * t; ahead of
// the front its clock stands, so it starts its cycle where it stood when the front reaches it.
TEST(Effects, GrowthOnlyBehindTheProliferativeFront) {
  State s = line_cell(10, 0, 5);  // centroid x = 20 um
  const auto r0 = rules_of("  growth: {cycle_time: 20, front: {x0: 0.0, speed: 2.0}}\n", s);
  ASSERT_EQ(r0.growth_p[3], 1);  // clock.h: the front's flag
  s.cell_fields["growth.clock"] = {0.0};
  CellRules r = r0;
  semlb_cell_stage_at(&r, 9.0);  // front at 18 um: the cell is ahead of it
  EXPECT_FALSE(stage(s, r, 2.0));
  EXPECT_EQ(s.elements(), 10);
  EXPECT_EQ(s.cell_fields["growth.clock"][0], 0.0);  // quiescent: the clock stands
  semlb_cell_stage_at(&r, 10.0);                     // front at 20 um = the centroid: behind (<=) counts
  EXPECT_TRUE(stage(s, r, 2.0));
  EXPECT_EQ(s.elements(), 11);
}

// Without a front the rule is today's (the same clock and births whatever the centroid); a bad front is refused
// with its field.
TEST(Effects, GrowthFrontNeedsBothSettings) {
  State s = line_cell(10, 0, 5);
  EXPECT_EQ(rules_of("  growth: {cycle_time: 20}\n", s).growth_p[3], 0);
  for (const char* bad : {"front: {x0: 1.0}", "front: {speed: 1.0}", "front: {x0: 1, speed: 1, width: 3}",
                          "front: {x0: 1, speed: fast}"}) {
    try {
      rules_of(std::string("  growth: {") + bad + "}\n", s);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("effects.growth.front."), std::string::npos) << e.what();
    }
  }
}

// A whole development run with a front on every backend: the same cells bit for bit on the C++ backends and
// the same cell counts on OpenCL (cells.h is shared); cells far ahead of the front never grew (a cell born
// full, 20 elements, divides at once whatever the front: left out).
TEST(Effects, ProliferativeFrontRunsAlikeOnEveryBackend) {
  const std::vector<std::string> front = {"tissue.cells=40", "effects.growth.front={x0: 10.0, speed: 0.5}"};
  std::map<std::string, State> out;
  for (const auto& backend : testing::available_backends()) {
    auto sets = front;
    sets.push_back("backend.name=" + backend);
    auto scene = load_scene(std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml", sets);
    Simulation sim(scene, make_tissue(scene));
    const State start = sim.host_state();
    sim.advance(2000);  // 20 h: the front at 20 um
    out[backend] = sim.sync();
    const State& s = out[backend];
    EXPECT_GT(s.elements(), start.elements()) << backend;  // cells behind the front grew
    for (long c = 0; c < start.cells(); ++c) {  // a cell starting 15 um ahead of the final front grew nothing
      if (centroid(start, c)[0] > 35.0 && start.cell_count[c] < 20) {
        EXPECT_EQ(s.cell_count[c], start.cell_count[c]) << backend << " cell " << c;
      }
    }
  }
  EXPECT_EQ(out.at("serial").hash(), out.at("cpu-binned").hash());
  for (const char* device : {"opencl-allpairs", "opencl-binned"})
    if (out.count(device)) {
      EXPECT_EQ(out.at(device).cell_count, out.at("serial").cell_count) << device;
      EXPECT_EQ(out.at(device).cell_type, out.at("serial").cell_type) << device;
    }
}

TEST(Effects, DivisionSplitsAcrossTheLongAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    State s = line_cell(20, axis, 10);
    const auto r = rules_of("  division: {at_elements: 20}\n", s);
    ASSERT_TRUE(stage(s, r, 0.1));
    ASSERT_EQ(s.cells(), 2);
    EXPECT_EQ(s.cell_count[0] + s.cell_count[1], 20);
    EXPECT_EQ(s.cell_count[0], 10);
    EXPECT_EQ(s.cell_id[1], 5u | (1u << kRootIdBits));  // first division of cell 5
    EXPECT_EQ(s.cell_fields.at("division.depth"), std::vector<double>({1, 1}));
    // every element of the mother lies below every element of the daughter along the axis
    double mother_max = -1e9, daughter_min = 1e9;
    for (int k = 0; k < s.cell_count[0]; ++k) mother_max = std::max(mother_max, s.position[3 * k + axis]);
    for (int k = 0; k < s.cell_count[1]; ++k)
      daughter_min = std::min(daughter_min, s.position[3 * (s.cell_first[1] + k) + axis]);
    EXPECT_LT(mother_max, daughter_min) << "axis " << axis;
  }
}

TEST(Effects, DivisionOfACoincidentClumpStillHalvesIt) {
  State s = line_cell(20, 0, 10);
  for (long e = 0; e < 20; ++e) s.position[3 * e] = 20;  // all elements on one point
  const auto r = rules_of("  division: {at_elements: 20}\n", s);
  ASSERT_TRUE(stage(s, r, 0.1));
  EXPECT_EQ(s.cell_count[0], 10);
  EXPECT_EQ(s.cell_count[1], 10);
}

// The fate rule on every backend: `stages` cell stages of `elapsed` h each (Backend::cell_fate) of state s.
void fates(State& s, const std::string& yaml, double elapsed, int stages, const std::string& backend) {
  if (!s.cell_fields.count("differentiation.age")) rules_of(yaml, s);  // declares differentiation.age (0 h)
  const auto params =
      testing::section_params("differentiation", yaml.substr(yaml.find('{')), FateRules::at("differentiation").read);
  auto b = testing::backend(backend, "double");
  b->upload(s);
  for (int k = 0; k < stages; ++k)
    b->cell_fate(s, fate_call("differentiation", params), cell_field_index(s, "differentiation.age"), elapsed);
  b->download(s);
}

TEST(Effects, DifferentiationFollowsHeightThenAge) {
  for (const auto& backend : testing::available_backends()) {
    const std::string rule = "  differentiation: {basal_height: 8, granular_after: 5}\n";
    State s = line_cell(10, 0, 12);  // centroid above basal_height = 8
    fates(s, rule, 1.0, 1, backend);
    EXPECT_EQ(s.cell_type[0], kSpinous) << backend;
    EXPECT_EQ(s.cell_fields.at("differentiation.age")[0], 0.0) << backend;  // a change resets the age
    fates(s, rule, 1.0, 4, backend);
    EXPECT_EQ(s.cell_type[0], kSpinous) << backend;
    EXPECT_EQ(s.cell_fields.at("differentiation.age")[0], 4.0) << backend;
    fates(s, rule, 1.0, 1, backend);
    EXPECT_EQ(s.cell_type[0], kGranular) << backend;
    State low = line_cell(10, 0, 4);
    fates(low, "  differentiation: {basal_height: 8}\n", 1.0, 1, backend);
    EXPECT_EQ(low.cell_type[0], kBasal) << backend;
    EXPECT_EQ(low.cell_fields.at("differentiation.age")[0], 1.0) << backend;
  }
}

TEST(Effects, UnknownEffectAndUnknownParameterAreRefusedWithTheirLine) {
  try {
    auto scene = scene_from(std::string(testing::kMechanicsYaml) + "  growht: {}\n");
    make_effects(scene);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("test.yaml:9: field 'effects.growht'"), std::string::npos) << e.what();
  }
  try {
    auto scene = scene_from(std::string(testing::kMechanicsYaml) + "  growth: {cycle_tim: 3}\n");
    make_effects(scene);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field 'effects.growth.cycle_tim': unknown setting"), std::string::npos)
        << e.what();
  }
}

TEST(Effects, EpidermisRunKeepsCountsConsistentWithGrowthAndDivision) {
  auto scene =
      load_scene(std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml", {"tissue.cells=8", "time.steps=10000"});
  Simulation sim(scene, make_tissue(scene));
  const long cells0 = sim.host_state().cells();
  sim.advance(10000);  // 100 h: five cell cycles
  const State& s = sim.sync();
  EXPECT_GT(s.cells(), cells0);  // divisions happened
  long sum = 0;
  std::set<uint64_t> ids(s.cell_id.begin(), s.cell_id.end());
  EXPECT_EQ(static_cast<long>(ids.size()), s.cells());
  for (long c = 0; c < s.cells(); ++c) {
    EXPECT_GE(s.cell_count[c], 1);
    EXPECT_LE(s.cell_count[c], 20);
    sum += s.cell_count[c];
  }
  EXPECT_EQ(sum, s.elements());
  for (double v : s.position) ASSERT_TRUE(std::isfinite(v));
  for (long e = 0; e < s.elements(); ++e) EXPECT_GT(s.position[3 * e + 2], -1.0);  // nothing fell through the membrane
}

// A decomposed run waits for the slowest rank in its ghost exchange, failure check and cell migration; a
// rank's phase timers (its computation time, what the controllers balance) must not include those waits.
TEST(Effects, CollectiveHooksOfTheCellStageAreNotTimedAsComputation) {
  auto scene = load_scene(std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml", {"tissue.cells=8"});
  Simulation sim(scene, make_tissue(scene));
  struct Napping : StepHooks {
    int exchanges = 0, checks = 0, migrations = 0;
    static void nap(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }
    unsigned mask() const override { return kBeforeForces | kFailureCheck | kAfterCells; }
    void before_forces() override { ++exchanges, nap(5); }
    void failure_check() override { ++checks, nap(30); }
    void after_cells() override { ++migrations, nap(30); }
  } hooks;
  sim.set_hooks(&hooks);
  const int &exchanges = hooks.exchanges, &checks = hooks.checks, &migrations = hooks.migrations;
  const auto t0 = std::chrono::steady_clock::now();
  sim.advance(4 * scene.cell_update_every);
  const double wall = seconds_since(t0);
  EXPECT_EQ(exchanges, 4 * scene.cell_update_every);  // one ghost exchange per step
  EXPECT_EQ(migrations, 4);
  EXPECT_GE(checks, 4);
  const double naps = 0.005 * exchanges + 0.03 * (checks + migrations);
  double timed = 0;
  for (double p : sim.phase_seconds()) timed += p;
  EXPECT_GE(wall, naps);
  EXPECT_LT(timed, wall - naps + 1e-3);  // the naps are in the wall time only
}

// A hook runs only at the points its mask names (StepHooks, as a LAMMPS fix's setmask): the others are never called,
// and a failure check left out of the mask is the simulation's own (which would throw on a failure).
TEST(Effects, StepHooksRunOnlyAtThePointsOfTheirMask) {
  auto scene = load_scene(std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml", {"tissue.cells=8"});
  Simulation sim(scene, make_tissue(scene));
  struct Counting : StepHooks {
    unsigned taken = 0;
    std::map<std::string, int> calls;
    unsigned mask() const override { return taken; }
    void before_forces() override { ++calls["before_forces"]; }
    void post_exchange() override { ++calls["post_exchange"]; }
    void before_nonlocal_forces() override { ++calls["before_nonlocal_forces"]; }
    void before_cells() override { ++calls["before_cells"]; }
    void after_cells() override { ++calls["after_cells"]; }
    void failure_check() override { ++calls["failure_check"]; }
  } hooks;
  hooks.taken = StepHooks::kBeforeCells | StepHooks::kPostExchange;
  sim.set_hooks(&hooks);
  const long steps = 2 * scene.cell_update_every;
  sim.advance(steps);
  EXPECT_EQ(hooks.calls, (std::map<std::string, int>{{"before_cells", 2}, {"post_exchange", static_cast<int>(steps)}}));
  hooks.calls.clear();
  hooks.taken =
      StepHooks::kBeforeForces | StepHooks::kBeforeNonlocalForces | StepHooks::kAfterCells | StepHooks::kFailureCheck;
  sim.advance(2 * steps);
  EXPECT_EQ(hooks.calls, (std::map<std::string, int>{{"after_cells", 2},
                                                     {"before_forces", static_cast<int>(steps)},
                                                     {"before_nonlocal_forces", static_cast<int>(steps)},
                                                     {"failure_check", 3}}));  // 2 cell updates and advance's end
  sim.set_hooks(nullptr);
  hooks.calls.clear();
  sim.advance(2 * steps + 1);
  EXPECT_TRUE(hooks.calls.empty());
}

}  // namespace
}  // namespace semlb::engine
