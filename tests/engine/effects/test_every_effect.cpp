// Every registered effect, each with its registered example section beside mechanics (a pair term: instead of it;
// growth and division once per registered growth law and division rule, with its example):
// the same state on every backend this machine runs (bit for bit between the C++ backends and between the OpenCL
// ones, within the stated 1e-9 um between the two kinds), and on 1, 2 and 4 ranks as on one device. A new effect is
// tested by being registered (Cabana's harness: one test body over every backend and rank count).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "common/text_io.hpp"
#include "engine/division/division_rule.hpp"
#include "engine/effects/effect.hpp"
#include "engine/growth/growth_law.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "engine/pairs/pair_term.hpp"
#include "engine/simulation/simulation.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

// One case: an effect and its section (the effect's example, or a growth law's or division rule's), named NAME or
// growth_LAW / division_RULE.
struct Case {
  std::string effect, section, name;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name << ": " << c.section; }  // gtest's name for the case
std::vector<Case> cases() {
  std::vector<Case> out;
  for (const auto& name : Effects::names())
    if (name == "growth")
      for (const auto& law : GrowthLaws::names()) out.push_back({name, GrowthLaws::at(law).example, name + "_" + law});
    else if (name == "division")
      for (const auto& rule : DivisionRules::names())
        out.push_back({name, DivisionRules::at(rule).example, name + "_" + rule});
    else
      out.push_back({name, Effects::at(name).example, name});
  return out;
}

// The effect beside mechanics, through --set on scenes/mechanics.yaml; a pair term instead of mechanics (a scene lists
// one), in a copy of that scene whose effects are the term's example alone.
class EveryEffect : public ::testing::TestWithParam<Case> {
 protected:
  const std::string& effect() const { return GetParam().effect; }
  bool pair() const {
    const auto names = PairTerms::names();
    return std::find(names.begin(), names.end(), effect()) != names.end();
  }
  std::string scene() const {
    const std::string shipped = test::source("scenes/mechanics.yaml");
    if (!pair()) return shipped;
    const std::string text = read_file(shipped),
                      path = test::fresh_dir("every_effect_scene_" + GetParam().name) + "/scene.yaml";
    write_file_atomically(
        path, text.substr(0, text.find("\neffects:")) + "\neffects:\n  " + effect() + ": " + GetParam().section + "\n");
    return path;
  }
  std::vector<std::string> set() const {
    if (pair()) return {};
    return {"effects." + effect() + "=" + GetParam().section};
  }
};

// 20 steps (two cell stages) of the mechanics scene's sheet of 60 cells with the effect, on `backend`.
State run(const std::string& scene_file, const std::string& backend, const std::string& precision,
          const std::vector<std::string>& effect) {
  std::vector<std::string> overrides = {"backend.name=" + backend, "backend.precision=" + precision, "tissue.cells=60",
                                        "time.steps=20", "time.cell_update_every=10"};
  overrides.insert(overrides.end(), effect.begin(), effect.end());
  auto scene = load_scene(scene_file, overrides);
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
  const std::string file = scene();
  const auto on = [&](const std::string& backend, const std::string& precision) {
    return run(file, backend, precision, set());
  };
  const State ref = on("serial", "double");
  EXPECT_EQ(on("cpu-binned", "double").hash(), ref.hash()) << "cpu-binned";
  const auto backends = testing::available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end())
    GTEST_SKIP() << "no OpenCL platform";
  const State binned = on("opencl-binned", "double");
  EXPECT_EQ(on("opencl-allpairs", "double").hash(), binned.hash()) << "opencl-allpairs";
  EXPECT_EQ(binned.cell_id, ref.cell_id);
  EXPECT_LT(max_difference(binned, ref), 1e-9);
  EXPECT_EQ(on("opencl-allpairs", "float").hash(), on("opencl-binned", "float").hash()) << "float";
}

TEST_P(EveryEffect, SameFinalStateOnOneTwoAndFourRanksAsOnOneDevice) {
  // 400 cells over ~140 um in x: room for 4 slabs; rebalanced every 20 steps, so cells migrate.
  std::string args =
      " --scene " + scene() +
      " --quiet --set tissue.cells=400 --set backend.cpu-binned.threads=1 --set decomposition.rebalance_every=20"
      " --set time.cell_update_every=10 --steps 60";
  for (const auto& s : set()) args += " --set '" + s + "'";
  const std::string dir = test::fresh_dir("every_effect_" + GetParam().name);
  testing::expect_same_state_on_ranks(args, dir);
  // run.csv's columns stay distinct with the effect's phase column (NAME_s) among them.
  const auto header = split(split(read_file(dir + "/single/run.csv"), '\n')[0], ',');
  const std::set<std::string> distinct(header.begin(), header.end());
  EXPECT_EQ(distinct.size(), header.size()) << read_file(dir + "/single/run.csv").substr(0, 200);
}

INSTANTIATE_TEST_SUITE_P(Registered, EveryEffect, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace semlb::engine
