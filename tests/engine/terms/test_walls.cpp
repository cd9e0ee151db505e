// The "walls" element term: the SEM Morse force of its faces by hand, confinement of a spreading tissue, and its
// scene errors.
#include <gtest/gtest.h>

#include <cmath>

#include "common/errors.hpp"
#include "engine/backends/backend.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/terms/term.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

std::vector<double> params(const std::string& yaml) {
  return testing::section_params("walls", yaml, ElementTerms::at("walls").read);
}

// The force on one element at (x, y, 5) from the walls of `yaml`, on the serial backend (double).
std::array<double, 3> force_at(double x, double y, const std::string& yaml) {
  State s;
  s.cell_id = {1};
  s.cell_type = {1};
  s.cell_count = {1};
  s.position = {x, y, 5};
  s.reindex();
  auto b = testing::backend("serial", "double");
  b->upload(s);
  b->zero_forces();
  b->element_term(element_term_call("walls", params(yaml)));
  const auto f = b->fixed_forces();
  return {f[0] * 0x1p-32, f[1] * 0x1p-32, f[2] * 0x1p-32};
}

TEST(Walls, EachFacePushesInwardWithTheMorseForceOfItsDistance) {
  const std::string walls =
      "{xlo: 0, xhi: 20, ylo: -5, yhi: 5, wall_U: 2, wall_xi: 0.5, adhesion_V: 1, adhesion_xi: 2}";
  auto morse = [](double d) { return 2 / 0.5 * std::exp(-d / 0.5) - 1 / 2.0 * std::exp(-d / 2.0); };
  // 0.3 um inside xlo, 19.7 um inside xhi; 4 um inside ylo, 6 um inside yhi.
  const auto f = force_at(0.3, -1, walls);
  EXPECT_NEAR(f[0], morse(0.3) - morse(19.7), 1e-9);
  EXPECT_NEAR(f[1], morse(4) - morse(6), 1e-9);
  EXPECT_EQ(f[2], 0.0);
  EXPECT_GT(f[0], 0);  // repulsion dominates close to the face: pushed toward +x, away from xlo
  EXPECT_LT(f[1], 0);  // 4 um from ylo, adhesion dominates there: pulled toward ylo (-y)
  // The hi face mirrors the lo face.
  EXPECT_NEAR(force_at(19.7, 0, walls)[0], -force_at(0.3, 0, walls)[0], 1e-9);
  // An element behind a face gets the clamped force (pushed back in, never NaN).
  EXPECT_EQ(force_at(-50, 0, walls)[0], 1048576.0);
  // Only the faces given: with xlo alone nothing acts along y, and far from xlo nothing at all.
  const auto one = force_at(1e4, 3, "{xlo: 0}");
  EXPECT_EQ(one[0], 0.0);
  EXPECT_EQ(one[1], 0.0);
}

TEST(Walls, ConfinesASpreadingTissueThatSpreadsWithoutIt) {
  // 60 cells of 9 elements packed into a 16 um cube repel each other outward; walls at x = 0 and 16 keep them in.
  const State start = testing::random_state(60, 9, 16.0, 3);
  auto extent = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> set = {"time.dt=0.01"};
    set.insert(set.end(), extra.begin(), extra.end());
    auto scene = testing::scene_from(testing::kMechanicsYaml, set);
    Simulation sim(scene, start);
    sim.advance(200);
    const State s = sim.sync();
    double lo = 1e9, hi = -1e9;
    for (long e = 0; e < s.elements(); ++e) lo = std::min(lo, s.position[3 * e]), hi = std::max(hi, s.position[3 * e]);
    return std::array<double, 2>{lo, hi};
  };
  const auto free = extent({});
  const auto walled = extent({"effects.walls={xlo: 0, xhi: 16}"});
  EXPECT_TRUE(free[0] < -1 || free[1] > 17) << "the tissue did not spread: " << free[0] << " .. " << free[1];
  EXPECT_GT(walled[0], -0.5);
  EXPECT_LT(walled[1], 16.5);
}

TEST(Walls, SceneErrorsNameTheField) {
  auto message = [](const std::string& yaml) { return testing::scene_error({"effects.walls=" + yaml}); };
  EXPECT_NE(message("{xlo: 5, xhi: 5}").find("effects.walls.xhi': must be above xlo (5 um)"), std::string::npos)
      << message("{xlo: 5, xhi: 5}");
  EXPECT_NE(message("{}").find("names no face"), std::string::npos) << message("{}");
  // A face inside the starting tissue (random_state: 2 cells in a 5 um box) is refused before the run, naming it,
  // rather than failing at step 0 on the clamped force; within wall_xi (0.5 um) of the face is allowed.
  const std::string inside = message("{xhi: 2}");
  EXPECT_EQ(inside.rfind("--set effects.walls: ", 0), 0u)
      << inside;  // (a scene file: FILE:LINE: field 'effects.walls': )
  EXPECT_NE(inside.find("start behind the face xhi = 2 um"), std::string::npos) << inside;
  EXPECT_EQ(message("{xhi: 5.4}"), "no error");
  EXPECT_NE(message("{ylo: 4}").find("behind the face ylo = 4 um (y down to"), std::string::npos)
      << message("{ylo: 4}");
  EXPECT_NE(message("{xlo: 0, xlow: 3}").find("xlow"), std::string::npos) << message("{xlo: 0, xlow: 3}");
  EXPECT_NE(message("{xlo: abc}").find("effects.walls.xlo"), std::string::npos) << message("{xlo: abc}");
}

}  // namespace
}  // namespace semlb::engine
