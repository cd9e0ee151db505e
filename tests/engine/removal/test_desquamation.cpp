// The "desquamation" effect: an epidermis sheds every cell whose centroid rises above the height, the same cells
// on every backend and on 1, 2 and 4 ranks bit for bit, ids are never given again, and its scene errors.
#include <gtest/gtest.h>

#include <set>

#include "../../run_command.hpp"
#include "common/errors.hpp"
#include "engine/effects/effect.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "engine/simulation/simulation.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

using test::fresh_dir;
using test::run;
using test::semlb_bin;
using test::source;

const std::string kHeight = "9";  // um: the epidermis scene's cells stratify past it within 100 steps

// The epidermis scene on `backend` with desquamation, advanced one cell stage (10 steps) at a time for 100 steps;
// the initial state and the state after every stage.
std::vector<State> stages(const std::string& backend, const std::string& precision, bool shed = true) {
  std::vector<std::string> set = {"backend.name=" + backend, "backend.precision=" + precision, "tissue.cells=80"};
  if (shed) set.push_back("effects.desquamation={height: " + kHeight + "}");
  auto scene = load_scene(source("scenes/epidermis.yaml"), set);
  Simulation sim(scene, make_tissue(scene));
  std::vector<State> out = {sim.sync()};  // the initial state, then after each stage
  for (long step = 10; step <= 100; step += 10) {
    sim.advance(step);
    out.push_back(sim.sync());
  }
  return out;
}

TEST(Desquamation, ShedsEveryCellAboveTheHeightAndNeverGivesItsIdAgain) {
  const auto shed = stages("cpu-binned", "double");
  const auto kept = stages("cpu-binned", "double", false);
  EXPECT_LT(shed.back().cells(), kept.back().cells()) << "nothing was shed";
  std::set<uint64_t> gone;
  for (size_t k = 0; k < shed.size(); ++k) {
    const State& s = shed[k];
    for (long c = 0; c < s.cells(); ++c) {  // right after a cell stage: no centroid above the height
      if (k > 0) {
        EXPECT_LE(centroid(s, c)[2], std::stod(kHeight)) << "stage " << k << ", cell " << s.cell_id[c];
      }
      EXPECT_EQ(gone.count(s.cell_id[c]), 0u) << "id " << s.cell_id[c] << " given again at stage " << k;
    }
    if (k + 1 < shed.size()) {
      std::set<uint64_t> now(s.cell_id.begin(), s.cell_id.end()),
          next(shed[k + 1].cell_id.begin(), shed[k + 1].cell_id.end());
      for (uint64_t id : now)
        if (!next.count(id)) gone.insert(id);
    }
  }
  EXPECT_FALSE(gone.empty());
}

TEST(Desquamation, SameCellsOnEveryBackend) {
  const auto reference = stages("serial", "double").back();
  EXPECT_EQ(stages("cpu-binned", "double").back().hash(), reference.hash()) << "cpu-binned";
  const auto backends = testing::available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end())
    GTEST_SKIP() << "no OpenCL platform";
  for (const char* b : {"opencl-allpairs", "opencl-binned"}) {
    const auto s = stages(b, "double").back();
    EXPECT_EQ(s.canonical().cell_id, reference.canonical().cell_id) << b;  // positions within the stated 1e-9 um
  }
  EXPECT_EQ(stages("opencl-allpairs", "float").back().hash(), stages("opencl-binned", "float").back().hash());
}

TEST(Desquamation, SameFinalStateOnOneTwoAndFourRanksAsOnOneDevice) {
  const auto dir = fresh_dir("desquamation_ranks");
  const std::string args =
      " --scene " + source("scenes/epidermis.yaml") +
      " --quiet --set tissue.cells=400 --set backend.cpu-binned.threads=1 --set decomposition.rebalance_every=50"
      " --steps 150";
  const State single =
      testing::expect_same_state_on_ranks(args + " --set 'effects.desquamation={height: " + kHeight + "}'", dir);
  const auto plain = run(semlb_bin() + " sim" + args + " --out " + dir + "/plain");
  ASSERT_EQ(plain.rc, 0) << plain.out;
  EXPECT_LT(single.cells(), read_state(dir + "/plain/final.h5").cells()) << "nothing was shed";
}

TEST(Desquamation, SceneErrorsNameTheField) {
  auto message = [](const std::string& yaml) { return testing::scene_error({"effects.desquamation=" + yaml}); };
  EXPECT_NE(message("{}").find("effects.desquamation.height': is required"), std::string::npos) << message("{}");
  EXPECT_NE(message("{height: -1}").find("effects.desquamation.height"), std::string::npos) << message("{height: -1}");
  EXPECT_NE(message("{height: 1e}").find("effects.desquamation.height"), std::string::npos) << message("{height: 1e}");
  EXPECT_NE(message("{height: 5, hieght: 3}").find("hieght"), std::string::npos) << message("{height: 5, hieght: 3}");
  // A misspelt key alone is named as such, not as a missing height.
  EXPECT_NE(message("{heigth: 9}").find("'effects.desquamation.heigth': unknown setting (known: height)"),
            std::string::npos)
      << message("{heigth: 9}");
}

}  // namespace
}  // namespace semlb::engine
