// Numerical hard cases: coincident elements, a 10x dense clump, a newborn on top of an element, and
// the largest stable time step against one beyond it (which must stop with step, element, quantity).
#include <gtest/gtest.h>

#include <cmath>

#include "engine/simulation/simulation.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

using testing::available_backends;
using testing::scene_from;

Scene hard_scene(const std::string& backend, double dt) {
  auto scene = scene_from(testing::kMechanicsYaml,
                          {"backend.name=" + backend, "time.dt=" + std::to_string(dt), "effects.membrane={}"});
  scene.box_lo = {-20, -20, -20};
  scene.box_hi = {60, 60, 60};
  return scene;
}

bool finite(const State& s) {
  for (double v : s.position)
    if (!std::isfinite(v)) return false;
  return true;
}

TEST(HardCases, CoincidentElementsSeparateAndStayFinite) {
  State s = testing::random_state(4, 6, 1.0, 3);
  for (long e = 0; e < s.elements(); ++e)
    for (int d = 0; d < 3; ++d) s.position[3 * e + d] = 10.0;  // 24 elements of 4 cells on one point
  for (const auto& backend : available_backends()) {
    auto scene = hard_scene(backend, 0.01);
    Simulation sim(scene, s);
    sim.advance(200);
    const State& out = sim.sync();
    ASSERT_TRUE(finite(out)) << backend;
    double spread = 0;
    for (long e = 0; e < out.elements(); ++e) spread = std::max(spread, std::abs(out.position[3 * e] - 10.0));
    EXPECT_GT(spread, 0.1) << backend;  // they did move apart
  }
}

TEST(HardCases, DenseClumpAtTenTimesNormalDensityStaysFinite) {
  // Normal tissue: ~15 elements per cutoff cube (8.75 um)^3; here 150 per cube.
  State s = testing::random_state(40, 15, 8.75 * std::cbrt(600.0 / 150.0), 4);
  for (const auto& backend : available_backends()) {
    auto scene = hard_scene(backend, 0.01);
    Simulation sim(scene, s);
    sim.advance(100);
    EXPECT_TRUE(finite(sim.sync())) << backend;
  }
}

TEST(HardCases, NewbornOnTopOfAnExistingElementIsPushedOff) {
  State s = testing::random_state(2, 10, 8.0, 5);
  s.position.insert(s.position.end(), s.position.begin(), s.position.begin() + 3);  // copy of element 0
  s.cell_count[1] += 1;
  s.reindex();
  for (const auto& backend : available_backends()) {
    auto scene = hard_scene(backend, 0.01);
    Simulation sim(scene, s);
    sim.advance(50);
    const State& out = sim.sync();
    ASSERT_TRUE(finite(out)) << backend;
    const long last = out.elements() - 1;
    double d2 = 0;
    for (int d = 0; d < 3; ++d) d2 += std::pow(out.position[d] - out.position[3 * last + d], 2);
    EXPECT_GT(d2, 1e-4) << backend;
  }
}

// Tissue from the default generator: dt = 0.1 h is the largest stable step we document (docs/engine.md);
// dt = 2 h must stop with a message naming the step, the element and the quantity.
TEST(HardCases, LargestStableStepRunsAndOneBeyondStopsWithAMessage) {
  for (const auto& backend : available_backends()) {
    auto stable =
        scene_from(testing::kMechanicsYaml, {"backend.name=" + backend, "time.dt=0.1", "effects.membrane={}"});
    stable.box_lo = {-10, -10, -10};
    stable.box_hi = {80, 80, 40};
    Simulation ok(stable, testing::random_state(40, 15, 30.0, 6));
    ok.advance(300);
    EXPECT_TRUE(finite(ok.sync())) << backend;

    auto beyond = stable;
    beyond.dt = 2.0;
    Simulation bad(beyond, testing::random_state(40, 15, 30.0, 6));
    try {
      bad.advance(300);
      FAIL() << backend << " did not stop";
    } catch (const SimulationError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("step ", 0), 0u) << m;
      EXPECT_NE(m.find(": element "), std::string::npos) << m;
      EXPECT_NE(m.find("displacement exceeds time.max_displacement"), std::string::npos) << m;
    }
  }
}

// 1500 elements in a 1.5-um box with U0 = 1e7: every pair force at the 2^20 clamp, ~1500 partners each, so the |forces|
// on an element add up to ~1.6e9 force units, beyond the bound's 2^30 (an int64 of 2^-32 units holds 2^31). Every
// backend (and opencl-binned's neighbour list) stops at step 0 naming the element and the quantity, before any wrapped
// sum moves the tissue on; the same tissue with U0 = 1 runs.
TEST(HardCases, ForceSumsThatCouldLeaveInt64StopNamingTheElement) {
  const State s = testing::random_state(100, 15, 1.5, 8);
  std::vector<std::pair<std::string, std::string>> runs;
  for (const auto& backend : available_backends()) runs.emplace_back(backend, "0");
  if (runs.size() > 2) runs.emplace_back("opencl-binned", "0.5");
  for (const auto& [backend, skin] : runs) {
    // dt 0.01: every element also moves too far, and the force sums' stop still wins (the cause, not the symptom)
    for (const auto& [precision, dt] : {std::pair{"double", "0.01"}, std::pair{"float", "1e-12"}}) {
      auto scene = scene_from(testing::kMechanicsYaml,
                              {"backend.name=" + backend, "backend.opencl-binned.skin=" + skin,
                               std::string("backend.precision=") + precision, std::string("time.dt=") + dt,
                               "effects.mechanics={intra: {U0: 1e7, V0: 0}, inter: {U0: 1e7, V0: 0}}"});
      Simulation sim(scene, s);
      try {
        sim.advance(2);
        ADD_FAILURE() << backend << " " << precision << " skin " << skin << " did not stop";
      } catch (const SimulationError& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.rfind("step 0: element ", 0), 0u) << m;
        EXPECT_NE(m.find("force sum beyond the fixed-point range"), std::string::npos) << m;
        EXPECT_NE(m.find("more than 2^30 force units"), std::string::npos) << m;
      }
    }
    auto weak = scene_from(testing::kMechanicsYaml,
                           {"backend.name=" + backend, "backend.opencl-binned.skin=" + skin, "time.dt=1e-6"});
    Simulation ok(weak, s);
    EXPECT_NO_THROW(ok.advance(2)) << backend;
  }
}

TEST(HardCases, NonFinitePositionIsNamed) {
  State s = testing::random_state(3, 4, 10.0, 7);
  s.position[3 * 5 + 1] = std::nan("");
  auto scene = hard_scene("cpu-binned", 0.01);
  Simulation sim(scene, s);
  try {
    sim.advance(3);
    FAIL();
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("step 0: element 5 (cell 10, slot 1): position is not finite"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace semlb::engine
