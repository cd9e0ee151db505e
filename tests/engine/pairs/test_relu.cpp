// The relu pair term (pairs/relu.h, ya||a's piecewise-linear force): the law by hand, its sets, its scene errors.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/pairs/pair_term.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

using testing::pair_force_x;

TEST(Relu, PiecewiseLinearForceByHand) {
  const PairForces f =
      testing::pair_forces("relu", "{intra: {k_rep: 2, k_adh: 0.5, r0: 4, r_max: 6}, inter: {k_adh: 0.1}}", 8.75);
  const int a = phys64::semlb_info_pack(0, 0), b = phys64::semlb_info_pack(1, 1);
  // intra: f = 2 max(4 - r, 0) - 0.5 max(r - 4, 0) for r < 6
  EXPECT_NEAR(pair_force_x(f, 1.0, a, a), 6.0, 1e-9);
  EXPECT_NEAR(pair_force_x(f, 4.0, a, a), 0.0, 1e-9);
  EXPECT_NEAR(pair_force_x(f, 5.5, a, a), -0.75, 1e-9);
  EXPECT_EQ(pair_force_x(f, 6.0, a, a), 0.0);  // lets go at r_max
  EXPECT_EQ(pair_force_x(f, 7.0, a, a), 0.0);
  // inter: the defaults k_rep 1, r0 5, r_max 7 with k_adh 0.1
  EXPECT_NEAR(pair_force_x(f, 3.0, a, b), 2.0, 1e-9);
  EXPECT_NEAR(pair_force_x(f, 6.5, a, b), -0.15, 1e-9);
  EXPECT_EQ(pair_force_x(f, 7.0, a, b), 0.0);
  // the force is along d = Y_i - Y_j: repulsion pushes i away from j, in any direction
  int64_t acc[4] = {0, 0, 0, 0};
  PairTerms::at("relu").f64(0, -3.0, 0, a, a, 1, 2, f.params.data(), f.cutoff * f.cutoff, acc);
  EXPECT_NEAR(static_cast<double>(acc[1]) * SEMLB_FIXED_INV, -2.0, 1e-9);
  // coincident: |F| = f(0) = k_rep r0 = 8
  int64_t c[4];
  EXPECT_NEAR(testing::coincident_kick(PairTerms::at("relu").f64, f.params, f.cutoff * f.cutoff, a, 100, 101, c), 8.0,
              1e-6);
}

// A scene with relu as its pair term and `set` overriding its section.
std::string relu_error(const std::string& set, const std::string& cutoff = "8.75") {
  return testing::scene_error({"cutoff=" + cutoff, "effects=" + std::string("{relu: ") + set + "}"});
}

TEST(Relu, BadSectionsNameTheFieldAndTheCutoff) {
  std::string m = relu_error("{intra: {r_max: 9}}");
  EXPECT_NE(m.find("effects.relu.intra.r_max"), std::string::npos) << m;
  EXPECT_NE(m.find("cutoff (8.75 um)"), std::string::npos) << m;
  m = relu_error("{inter: {r0: 7, r_max: 6}}");
  EXPECT_NE(m.find("effects.relu.inter.r_max"), std::string::npos) << m;
  EXPECT_NE(m.find("must be below r_max"), std::string::npos) << m;
  m = relu_error("{inter: {k_rep: -1}}");
  EXPECT_NE(m.find("effects.relu.inter.k_rep"), std::string::npos) << m;
  m = relu_error("{intra: {r0: 0}}");
  EXPECT_NE(m.find("effects.relu.intra.r0"), std::string::npos) << m;
  m = relu_error("{intra: {k_spring: 1}}");
  EXPECT_NE(m.find("effects.relu.intra.k_spring"), std::string::npos) << m;
  EXPECT_EQ(relu_error("{intra: {r_max: 8.75}}"), "no error");  // at the cutoff itself: allowed
  m = relu_error("{intra: {k_rep: 0}}");                        // coincident elements would never part
  EXPECT_NE(m.find("effects.relu.intra.k_rep"), std::string::npos) << m;
  m = relu_error("{}", "6");  // the default r_max (7 um) beyond a cutoff of 6 um: refused, not shortened
  EXPECT_NE(m.find("effects.relu.intra.r_max"), std::string::npos) << m;
  EXPECT_NE(m.find("7 um (the default) is beyond the scene's cutoff (6 um)"), std::string::npos) << m;
}

}  // namespace
}  // namespace semlb::engine
