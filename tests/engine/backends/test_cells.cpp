// The cell stage's core (physics/cells.h) piece by piece, and the device cell stage (OpenCL on PoCL)
// against the host reference (serial) over a run in which cells grow, divide and differentiate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine/backends/backend.hpp"
#include "engine/division/division_rule.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "engine/simulation/simulation.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

using namespace cellrules;

// The long axis of the gyration tensor diag(l) rotated by R (columns: the eigenvectors).
std::array<double, 3> axis_of(const double (&R)[3][3], const std::array<double, 3>& l) {
  double g[3][3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) g[i][j] += R[i][k] * l[k] * R[j][k];
  const double packed[6] = {g[0][0], g[0][1], g[0][2], g[1][1], g[1][2], g[2][2]};
  std::array<double, 3> a{};
  semlb_cell_long_axis(packed, a.data());
  return a;
}

TEST(Cells, JacobiFindsTheLongAxisOfHandMadeEllipsoids) {
  const double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_EQ(axis_of(I, {1, 9, 4}), (std::array<double, 3>{0, 1, 0}));  // diagonal: no rotation at all
  // axis-aligned degenerate: two equal long axes; the tie goes to the lowest index
  EXPECT_EQ(axis_of(I, {4, 4, 1}), (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(axis_of(I, {1, 4, 4}), (std::array<double, 3>{0, 1, 0}));
  // a diagonal long axis (1, 1, 1)/sqrt 3 of an ellipsoid with axes 9, 2, 1
  const double s3 = 1 / std::sqrt(3.0), s2 = 1 / std::sqrt(2.0), s6 = 1 / std::sqrt(6.0);
  const double R[3][3] = {{s3, s2, s6}, {s3, -s2, s6}, {s3, 0, -2 * s6}};
  for (double v : axis_of(R, {9, 2, 1})) EXPECT_NEAR(v, s3, 1e-14);
  // the sign: the largest |component| is positive, whichever sign the rotation gives
  const double S[3][3] = {
      {1 / std::sqrt(5.0), 2 / std::sqrt(5.0), 0}, {-2 / std::sqrt(5.0), 1 / std::sqrt(5.0), 0}, {0, 0, 1}};
  const auto a = axis_of(S, {7, 3, 1});
  EXPECT_NEAR(a[0], -1 / std::sqrt(5.0), 1e-14);
  EXPECT_NEAR(a[1], 2 / std::sqrt(5.0), 1e-14);
  EXPECT_NEAR(a[2], 0, 1e-14);
}

// Coincident elements have no axis: the halves follow the stable order by projection (all 0), i.e. slot order.
TEST(Cells, CoincidentElementsSplitInHalvesBySlot) {
  State s;
  s.cell_id = {3};
  s.cell_type = {kBasal};
  s.cell_count = {21};
  s.position.assign(3 * 21, 2.5);
  s.reindex();
  s.cell_fields["division.depth"] = {0};  // the record: one field, the division's depth at index 0
  CellRules r{};
  const auto rules = DivisionRules::names();
  r.growth = r.growth_field = -1;
  r.division = static_cast<int>(std::find(rules.begin(), rules.end(), "long_axis") - rules.begin());
  r.division_p[0] = 1;   // basal only
  r.division_p[1] = 20;  // at 20 elements
  r.fields = 1;
  r.depth_field = 0;
  ASSERT_TRUE(run_cell_stage(s, r, 1, 0.1, 0));
  EXPECT_EQ(s.cell_count, (std::vector<int>{10, 11}));  // n / 2 stay, the rest leave
  EXPECT_EQ(s.cell_id, (std::vector<uint64_t>{3, daughter_id(3, 0)}));
  EXPECT_EQ(s.cell_fields.at("division.depth"), (std::vector<double>{1, 1}));
  for (double x : s.position) EXPECT_EQ(x, 2.5);
}

// The same small epidermis grown, divided and differentiated by serial (host reference) and opencl-binned
// (device kernels on PoCL). Tolerances (um after 600 steps, 60 cell stages): the cell stage itself is the same
// double arithmetic on both sides (only the growth draws' log/cos may differ by ulps), but the element stage
// differs by float/exp ulps each step (1e-9 um per 5 steps in double, 1e-3 in float: OpenClMatchesTheCppReference)
// and the overdamped dynamics carry such differences along: double 1e-6, float 0.05.
TEST(Cells, OpenClCellStageMatchesTheHostReference) {
  const auto backends = testing::available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end())
    GTEST_SKIP() << "no OpenCL platform";
  for (const char* precision : {"double", "float"}) {
    std::vector<State> out;
    for (const char* backend : {"serial", "opencl-binned"}) {
      auto scene = load_scene(
          std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml",
          {"tissue.cells=12", "backend.name=" + std::string(backend), "backend.precision=" + std::string(precision),
           "effects.growth.cycle_time=1", "effects.differentiation.basal_height=2",
           "effects.differentiation.granular_after=1", "effects.noise.diffusion=0"});
      Simulation sim(scene, make_tissue(scene));
      sim.advance(600);
      out.push_back(sim.sync().canonical());
    }
    const State &ref = out[0], &dev = out[1];
    ASSERT_EQ(ref.cell_id, dev.cell_id) << precision;
    EXPECT_EQ(ref.cell_type, dev.cell_type) << precision;
    EXPECT_EQ(ref.cell_count, dev.cell_count) << precision;
    EXPECT_GT(ref.cells(), 12) << "divisions happened";
    EXPECT_GT(std::count(ref.cell_type.begin(), ref.cell_type.end(), kGranular), 0) << "spinous -> granular happened";
    for (const auto& [name, f] : ref.cell_fields) {
      ASSERT_EQ(f.size(), dev.cell_fields.at(name).size()) << name;
      for (size_t c = 0; c < f.size(); ++c) EXPECT_NEAR(f[c], dev.cell_fields.at(name)[c], 1e-9) << name;
    }
    double worst = 0;
    for (size_t i = 0; i < ref.position.size(); ++i)
      worst = std::max(worst, std::abs(ref.position[i] - dev.position[i]));
    std::printf("%s: %ld cells, max position difference %.3g um\n", precision, ref.cells(), worst);
    EXPECT_LT(worst, std::string(precision) == "double" ? 1e-6 : 0.05) << precision;
  }
}

}  // namespace
}  // namespace semlb::engine
