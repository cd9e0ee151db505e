// The evaluator header: Morse force, exact antisymmetry, coincident elements, fixed-point sums.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "engine/backends/cpu_physics.hpp"

namespace semlb::engine {
namespace {

std::vector<double> table() {
  std::vector<double> t(SEMLB_TABLE_SIZE);
  for (int s = 0; s < SEMLB_TABLE_SIZE; s += 4) {  // U0 = 2.86, V0 = 1 (intra) or 0.5, xi1 = 1, xi2 = 2
    t[s] = 2.86 / 1.0;
    t[s + 1] = 1 / 1.0;
    t[s + 2] = (s == 0 ? 1.0 : 0.5) / 2.0;
    t[s + 3] = 1 / 2.0;
  }
  return t;
}

TEST(Evaluator, MorseForceVanishesAtTheDocumentedEquilibrium) {
  const auto t = table();
  // r* = ln(U0 xi2 / (V0 xi1)) / (1/xi1 - 1/xi2) = 2 ln(5.72) = 3.488 um for the intra set.
  const double r_star = std::log(2.86 * 2.0 / 1.0) / (1.0 - 0.5);
  EXPECT_NEAR(phys64::semlb_morse_magnitude(r_star, t.data()), 0.0, 1e-12);
  EXPECT_GT(phys64::semlb_morse_magnitude(r_star - 0.5, t.data()), 0.0);  // repulsive inside
  EXPECT_LT(phys64::semlb_morse_magnitude(r_star + 0.5, t.data()), 0.0);  // adhesive outside
}

TEST(Evaluator, PairForcesAreExactlyAntisymmetric) {
  const auto t = table();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-6, 6);
  for (int k = 0; k < 1000; ++k) {
    const double d[3] = {u(rng), u(rng), u(rng)};
    int64_t a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
    const int info_i = 4 | (k % 3), info_j = 8 | ((k / 3) % 3);
    Physics<double>::pair(d[0], d[1], d[2], info_i, info_j, 5, 9, t.data(), 8.75 * 8.75, a);
    Physics<double>::pair(-d[0], -d[1], -d[2], info_j, info_i, 9, 5, t.data(), 8.75 * 8.75, b);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(a[c], -b[c]);
  }
}

TEST(Evaluator, CoincidentElementsGetAFiniteOppositeKick) {
  const auto t = table();
  int64_t a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
  Physics<double>::pair(0, 0, 0, 4, 4, 100, 101, t.data(), 1.0, a);
  Physics<double>::pair(0, 0, 0, 4, 4, 101, 100, t.data(), 1.0, b);
  double norm = 0;
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(a[c], -b[c]);
    norm += std::pow(static_cast<double>(a[c]) * SEMLB_FIXED_INV, 2);
  }
  // |F| = f(0) = U0/xi1 - V0/xi2 = 2.36 for the intra set
  EXPECT_NEAR(std::sqrt(norm), 2.86 - 0.5, 1e-6);
}

TEST(Evaluator, FixedPointSumsDoNotDependOnOrder) {
  const auto t = table();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> u(-5, 5);
  std::vector<std::array<float, 3>> others(200);
  for (auto& o : others) o = {u(rng), u(rng), u(rng)};
  const std::vector<float> tf(t.begin(), t.end());
  auto sum = [&] {
    int64_t acc[3] = {0, 0, 0};
    for (const auto& o : others) Physics<float>::pair(o[0], o[1], o[2], 4, 9, 1, 2, tf.data(), 76.5f, acc);
    return std::array<int64_t, 3>{acc[0], acc[1], acc[2]};
  };
  const auto first = sum();
  for (int k = 0; k < 20; ++k) {
    std::shuffle(others.begin(), others.end(), rng);
    ASSERT_EQ(sum(), first);
  }
}

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
