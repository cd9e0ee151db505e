// Reactive rule (paper eqs. 2-4): hand-computed cases, threshold, direction, rounding, truncation, edge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/errors.hpp"
#include "controllers/policy.hpp"
#include "controllers/reactive.hpp"

using namespace semlb;

namespace {
Observation obs(std::vector<int> b, std::vector<double> t, int slices, int min_width) {
  Observation o;
  o.slices = slices;
  o.min_width = min_width;
  o.boundaries = std::move(b);
  o.times = std::move(t);
  validate(o);
  return o;
}
std::vector<int> decide(const Observation& o, PolicyParams p = {}) { return make_policy("reactive", p)->decide(o); }
}  // namespace

TEST(Reactive, HandComputedStepTowardSlowerRank) {
  // I = 0.5/1.25 = 0.4; |Δs| = 0.5 * 50 * 0.5 / (2 * 1.5) = 4.1667 -> 4, right rank slower -> boundary +4.
  EXPECT_EQ(decide(obs({50}, {1.0, 1.5}, 100, 4)), std::vector<int>{54});
  EXPECT_EQ(decide(obs({50}, {1.5, 1.0}, 100, 4)), std::vector<int>{46});
  const auto p = reactive_proposals(obs({50}, {1.0, 1.5}, 100, 4), {});
  EXPECT_NEAR(p[0].local_imbalance, 0.4, 1e-15);
  EXPECT_NEAR(p[0].magnitude, 0.5 * 50 * 0.5 / 3.0, 1e-12);
  EXPECT_EQ(p[0].n_slow, 50);
}

TEST(Reactive, ThresholdIsStrict) {
  EXPECT_EQ(decide(obs({50}, {1.0, 1.019}, 100, 4)), std::vector<int>{50});  // I = 0.0188 < tau
  EXPECT_EQ(decide(obs({50}, {1.0, 1.03}, 100, 4)), std::vector<int>{50});   // I = 0.0296 but |Δs| = 0.36 -> 0
  EXPECT_EQ(decide(obs({50}, {1.0, 1.1}, 100, 4)), std::vector<int>{51});    // |Δs| = 25 * 0.1 / 2.2 = 1.14 -> 1
  PolicyParams loose;
  loose.set("tau", "0.1");  // I = 0.0952 is now below the threshold
  EXPECT_EQ(decide(obs({50}, {1.0, 1.1}, 100, 4), loose), std::vector<int>{50});
}

TEST(Reactive, RoundsHalfAwayFromZeroAndHandlesAZeroTime) {
  // T- = 0, T+ = 1: I = 2, |Δs| = 0.5 * 10 * 1 / 2 = 2.5 -> 3 (half away from zero).
  EXPECT_EQ(decide(obs({10}, {0.0, 1.0}, 20, 2)), std::vector<int>{13});
  EXPECT_EQ(decide(obs({10}, {1.0, 0.0}, 20, 2)), std::vector<int>{7});
  EXPECT_EQ(integer_step(-1, 2.5), -3);
  EXPECT_EQ(integer_step(1, 2.49), 2);
}

TEST(Reactive, NSlowIsTheWidthBeforeTheSweep) {
  // Both boundaries push slices out of the slow middle rank (width 10): each |Δs| = 0.5*10*99/200 = 2.475 -> 2.
  EXPECT_EQ(decide(obs({10, 20}, {1, 100, 1}, 30, 4)), (std::vector<int>{12, 18}));
  PolicyParams strong;
  strong.set("alpha", "1.0");  // |Δs| = 3.96 -> 4 each; b1 truncated so the middle rank keeps 4 slices
  EXPECT_EQ(decide(obs({8, 16}, {1, 100, 1}, 24, 4), strong), (std::vector<int>{12, 16}));
}

TEST(Reactive, EqualZeroAndMinimalCases) {
  EXPECT_EQ(decide(obs({10, 20}, {2, 2, 2}, 30, 4)), (std::vector<int>{10, 20}));
  EXPECT_EQ(decide(obs({10, 20}, {0, 0, 0}, 30, 4)), (std::vector<int>{10, 20}));
  EXPECT_TRUE(decide(obs({}, {3.0}, 30, 4)).empty());                           // P = 1
  EXPECT_EQ(decide(obs({4, 8}, {1, 50, 1}, 12, 4)), (std::vector<int>{4, 8}));  // P * min_width == slices
}

TEST(Reactive, NonFiniteOrNegativeTimesAreRejectedByName) {
  Observation o;
  o.slices = 20;
  o.min_width = 2;
  o.boundaries = {10};
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -1.0}) {
    o.times = {1.0, bad};
    try {
      validate(o);
      FAIL() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("times[1]"), std::string::npos) << e.what();
    }
  }
}

TEST(Registry, UnknownPolicyAndParameterAreErrors) {
  try {
    make_policy("nope");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("reactive"), std::string::npos);  // lists the known ones
  }
  PolicyParams p;
  p.set("tua", "0.1");
  EXPECT_THROW(make_policy("reactive", p), InputError);
  PolicyParams q;
  q.set("tau", "abc");
  EXPECT_THROW(make_policy("reactive", q), InputError);
  for (const char* name : {"static", "reactive", "persistence", "holt", "gru", "oracle"}) {
    const auto names = policy_names();
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
}
