// The evaluator header: the fixed-point clamp and the counter-based Gaussian stream (the pair laws and the pair
// loop's body: tests/engine/pairs).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "engine/physics/cpu_physics.hpp"

namespace semlb::engine {
namespace {

TEST(Evaluator, NanForcesBecomeAHugeStepNotASilentValue) {
  EXPECT_EQ(phys64::semlb_to_fixed(std::nan("")), phys64::semlb_to_fixed(SEMLB_FORCE_MAX));
  EXPECT_EQ(phys64::semlb_to_fixed(1e300), phys64::semlb_to_fixed(SEMLB_FORCE_MAX));
}

TEST(Evaluator, GaussianStreamHasUnitMomentsAndIsCounterBased) {
  double m = 0, v = 0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const double g = gaussian(7, static_cast<uint64_t>(k), 3, 0);
    m += g;
    v += g * g;
  }
  EXPECT_NEAR(m / n, 0.0, 0.01);
  EXPECT_NEAR(v / n, 1.0, 0.01);
  EXPECT_EQ(gaussian(7, 42, 3, 1), gaussian(7, 42, 3, 1));
  EXPECT_NE(gaussian(7, 42, 3, 1), gaussian(7, 42, 4, 1));
}

}  // namespace
}  // namespace semlb::engine
