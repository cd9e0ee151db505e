// Every registered effect, each with its registered example section beside mechanics: the same state on every
// backend this machine runs (bit for bit between the C++ backends and between the OpenCL ones, within the stated
// 1e-9 um between the two kinds), and on 1, 2 and 4 ranks as on one device. A new effect is tested by being
// registered (Cabana's harness: one test body over every backend and rank count).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "common/text_io.hpp"
#include "engine/effects/effect.hpp"
#include "engine/model/tissue.hpp"
#include "engine/run/simulation.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

class EveryEffect : public ::testing::TestWithParam<std::string> {
 protected:
  std::string set() const { return "effects." + GetParam() + "=" + effect_example(GetParam()); }
};

// 20 steps (two cell stages) of the mechanics scene's sheet of 60 cells with the effect, on `backend`.
State run(const std::string& backend, const std::string& precision, const std::string& effect) {
  auto scene = load_scene(test::source("scenes/mechanics.yaml"),
                          {"backend.name=" + backend, "backend.precision=" + precision, "tissue.cells=60", "time.steps=20",
                           "time.cell_update_every=10", effect});
  Simulation sim(scene, make_tissue(scene));
  sim.advance(20);
  return sim.sync().canonical();
}

double max_difference(const State& a, const State& b) {
  if (a.position.size() != b.position.size()) return INFINITY;
  double d = 0;
  for (size_t i = 0; i < a.position.size(); ++i) d = std::max(d, std::abs(a.position[i] - b.position[i]));
  return d;
}

TEST_P(EveryEffect, SameStateOnEveryBackend) {
  const State ref = run("serial", "double", set());
  EXPECT_EQ(run("cpu-binned", "double", set()).hash(), ref.hash()) << "cpu-binned";
  const auto backends = testing::available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end()) GTEST_SKIP() << "no OpenCL platform";
  const State binned = run("opencl-binned", "double", set());
  EXPECT_EQ(run("opencl-allpairs", "double", set()).hash(), binned.hash()) << "opencl-allpairs";
  EXPECT_EQ(binned.cell_id, ref.cell_id);
  EXPECT_LT(max_difference(binned, ref), 1e-9);
  EXPECT_EQ(run("opencl-allpairs", "float", set()).hash(), run("opencl-binned", "float", set()).hash()) << "float";
}

TEST_P(EveryEffect, SameFinalStateOnOneTwoAndFourRanksAsOnOneDevice) {
  // 400 cells over ~140 um in x: room for 4 slabs; rebalanced every 20 steps, so cells migrate.
  const std::string args = " --scene " + test::source("scenes/mechanics.yaml") +
                           " --quiet --set tissue.cells=400 --set backend.threads=1 --set decomposition.rebalance_every=20"
                           " --set time.cell_update_every=10 --steps 60 --set '" + set() + "'";
  const std::string dir = test::fresh_dir("every_effect_" + GetParam());
  testing::expect_same_state_on_ranks(args, dir);
  // run.csv's columns stay distinct with the effect's phase column (NAME_s) among them.
  const auto header = split(split(read_file(dir + "/single/run.csv"), '\n')[0], ',');
  const std::set<std::string> distinct(header.begin(), header.end());
  EXPECT_EQ(distinct.size(), header.size()) << read_file(dir + "/single/run.csv").substr(0, 200);
}

INSTANTIATE_TEST_SUITE_P(Registered, EveryEffect, ::testing::ValuesIn(effect_names()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace semlb::engine
