// The evaluator header: the fixed-point clamp, the pair bound and the counter-based Gaussian stream (the pair laws and the pair
// loop's body: tests/engine/pairs).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <type_traits>

#include "engine/physics/cpu_physics.hpp"

namespace semlb::engine {
namespace {

TEST(Evaluator, NanForcesBecomeAHugeStepNotASilentValue) {
  EXPECT_EQ(phys64::semlb_to_fixed(std::nan("")), phys64::semlb_to_fixed(SEMLB_FORCE_MAX));
  EXPECT_EQ(phys64::semlb_to_fixed(1e300), phys64::semlb_to_fixed(SEMLB_FORCE_MAX));
}

// The pair bound through the mantissa (SEMLB_REAL_BITS, as the OpenCL kernels and the C++ backends build it) equals
// the conversion floor(min(|f|, SEMLB_FORCE_MAX)) + 1 on integers, their neighbours one ulp away, halves (the
// rounding ties), a sweep over every 97th bit pattern up to the clamp, beyond it, and NaN / infinities.
template <class Real, class Bound>
void expect_bound_is_the_conversion(Bound bound) {
  auto want = [](Real f) {
    const Real x = std::isnan(f) ? static_cast<Real>(SEMLB_FORCE_MAX) : std::min(std::fabs(f), static_cast<Real>(SEMLB_FORCE_MAX));
    return static_cast<int64_t>(x) + 1;
  };
  long checked = 0, wrong = 0;
  auto check = [&](Real f) {
    for (Real v : {f, -f}) {
      ++checked;
      if (bound(v) != want(v) && ++wrong <= 5) ADD_FAILURE() << "f = " << v << ": " << bound(v) << " != " << want(v);
    }
  };
  const Real top = static_cast<Real>(SEMLB_FORCE_MAX), inf = std::numeric_limits<Real>::infinity();
  for (long k = 0; k <= static_cast<long>(SEMLB_FORCE_MAX); ++k) {
    const Real r = static_cast<Real>(k);
    check(r);
    check(std::nextafter(r, inf));
    check(std::nextafter(r, -inf));
    check(r + static_cast<Real>(0.5));
  }
  using Bits = std::conditional_t<sizeof(Real) == 4, uint32_t, uint64_t>;
  const Bits last = std::bit_cast<Bits>(static_cast<Real>(2 * SEMLB_FORCE_MAX)), stride = sizeof(Real) == 4 ? 97 : Bits{97} << 29;
  for (Bits b = 0; b <= last; b += stride) check(std::bit_cast<Real>(b));
  for (Real f : {Real(0), std::numeric_limits<Real>::denorm_min(), std::numeric_limits<Real>::min(), top, inf,
                 std::numeric_limits<Real>::max(), std::numeric_limits<Real>::quiet_NaN()})
    check(f);
  EXPECT_EQ(wrong, 0) << "of " << checked;
  EXPECT_GT(checked, 4'000'000);
}

TEST(Evaluator, PairBoundThroughTheMantissaIsTheConversion) {
  expect_bound_is_the_conversion<float>(phys32::semlb_force_bound);
  expect_bound_is_the_conversion<double>(phys64::semlb_force_bound);
  EXPECT_EQ(phys32::semlb_force_bound(2.5f), 3);  // the tie rounds to 2 (even): no correction
  EXPECT_EQ(phys32::semlb_force_bound(3.5f), 4);  // the tie rounds to 4: corrected to 3
  EXPECT_EQ(phys64::semlb_force_bound(std::nan("")), static_cast<int64_t>(SEMLB_FORCE_MAX) + 1);
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
