// Production balancers (gromacs_dlb, hoomd_balance, all_tensor, lammps_shift): hand-computed 2- and 3-rank
// cases, switch-on thresholds, per-event caps, the half-way limits, min-width truncation, zero and equal
// times, state and parameter ranges.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/errors.hpp"
#include "controllers/policy.hpp"

using namespace semlb;

namespace {
using B = std::vector<int>;

Observation obs(B b, std::vector<double> t, int slices, int min_width, std::vector<double> work = {}) {
  Observation o;
  o.slices = slices;
  o.min_width = min_width;
  o.boundaries = std::move(b);
  o.times = std::move(t);
  o.slice_work = std::move(work);
  validate(o);
  return o;
}

PolicyParams params(std::initializer_list<std::pair<const char*, const char*>> kv) {
  PolicyParams p;
  for (const auto& [k, v] : kv) p.set(k, v);
  return p;
}

B decide(const char* name, const Observation& o, PolicyParams p = {}) { return make_policy(name, p)->decide(o); }

std::vector<double> repeat(std::initializer_list<std::pair<int, double>> runs) {
  std::vector<double> v;
  for (const auto& [n, x] : runs) v.insert(v.end(), n, x);
  return v;
}
}  // namespace

// ---------------------------------------------------------------------------------------------- gromacs_dlb
TEST(GromacsDlb, HandComputedTwoAndThreeRanks) {
  // P=2, T = {1, 1.5}: mean 1.25, loss 0.25/1.5 = 0.167 >= 0.02 -> on. relax * |T - mean|/mean = 0.1 each,
  // not above the 10% cap: sizes 50 * 1.1 = 55, 50 * 0.9 = 45 (sum 100) -> boundary 55.
  EXPECT_EQ(decide("gromacs_dlb", obs({50}, {1.0, 1.5}, 100, 4)), B{55});
  EXPECT_EQ(decide("gromacs_dlb", obs({50}, {1.5, 1.0}, 100, 4)), B{45});
  // P=3, T = {1, 1, 2}: mean 4/3, relative deviations -1/4, -1/4, 1/2; relax * 1/2 = 0.25 > 0.1, so one
  // factor sc = 0.5 * 0.1 / 0.25 = 0.2 for the row: sizes 30 * 1.05 = 31.5, 31.5, 30 * 0.9 = 27 (sum 90).
  // Targets 31.5, 63 (inside the half-way bounds [15, 45], [45, 75]); lround(1.5) = 2 -> {32, 63}.
  EXPECT_EQ(decide("gromacs_dlb", obs({30, 60}, {1, 1, 2}, 90, 4)), (B{32, 63}));
}

TEST(GromacsDlb, TheTenPercentCapScalesTheWholeRow) {
  // T = {1, 2}: relax * (0.5/1.5) = 1/6 > 0.1 -> sc = 0.3: sizes 55, 45 -> 55 (uncapped: 50 * 7/6 -> 58).
  EXPECT_EQ(decide("gromacs_dlb", obs({50}, {1.0, 2.0}, 100, 4)), B{55});
  EXPECT_EQ(decide("gromacs_dlb", obs({50}, {1.0, 2.0}, 100, 4), params({{"cap", "0.5"}})), B{58});
}

TEST(GromacsDlb, SwitchesOnAtTwoPercentLossAndStaysOn) {
  auto p = make_policy("gromacs_dlb");
  // T = {1, 1.03}: loss 0.015/1.03 = 1.46% < 2%: DLB stays off, no move.
  EXPECT_EQ(p->decide(obs({500}, {1.0, 1.03}, 1000, 4)), B{500});
  EXPECT_EQ(p->save_state().at("dlb_on"), std::vector<double>{0.0});
  // T = {1, 1.05}: loss 2.38% -> on; size 500 * (1 + 0.5 * 0.025/1.025) = 506.1 -> 506.
  EXPECT_EQ(p->decide(obs({500}, {1.0, 1.05}, 1000, 4)), B{506});
  // On for good (-dlb auto): the 1.46% imbalance is now balanced too: 500 * (1 + 0.5 * 0.015/1.015) -> 504.
  EXPECT_EQ(p->decide(obs({500}, {1.0, 1.03}, 1000, 4)), B{504});
  EXPECT_EQ(p->save_state().at("dlb_on"), std::vector<double>{1.0});
  // A restored state decides like the policy that kept it; a fresh one does not.
  auto restored = make_policy("gromacs_dlb");
  restored->load_state(p->save_state());
  EXPECT_EQ(restored->decide(obs({500}, {1.0, 1.03}, 1000, 4)), B{504});
  EXPECT_THROW(restored->load_state({{"dlb_on", {0.5}}}), InputError);
  EXPECT_THROW(restored->load_state({{"level", {1.0}}}), InputError);
}

TEST(GromacsDlb, HalfWayLimitAndMinWidthSweep) {
  // widths {80, 4, 16}, T = {2, 0, 0}, cap 0.5: relative deviations 2, -1, -1 -> sc = 0.5 * 0.5 / 1 = 0.25:
  // sizes 40, 5, 20 (sum 65, x 100/65): cum 61.54, 69.23. Boundary 1 may not pass half-way into its old
  // right slab: [mid(80, 84), mid(84, 100)] = [82, 92] -> 82 (69 without the limit); boundary 0 -> 62.
  EXPECT_EQ(decide("gromacs_dlb", obs({80, 84}, {2, 0, 0}, 100, 2), params({{"cap", "0.5"}})), (B{62, 82}));
  // widths {4, 46, 50}, T = {3, 0, 0}, cap 0.9: sc = 0.45: sizes 0.4, 66.7, 72.5 (x 100/139.6): targets
  // 0.29 -> half-way bound 2, and 48.07. The sweep keeps rank 0 at min_width 4: {4, 48}.
  EXPECT_EQ(decide("gromacs_dlb", obs({4, 50}, {3, 0, 0}, 100, 4), params({{"cap", "0.9"}})), (B{4, 48}));
}

// -------------------------------------------------------------------------------------------- hoomd_balance
TEST(HoomdBalance, HandComputedTwoAndThreeRanks) {
  // P=2, T = {1, 1.5}: max/mean 1.2 > 1.02. Scale 1/(T/mean) = 1.25 and 0.833, limited to 5%: widths 52.5
  // and 47.5 (sum 100, the least-squares fit is exact) -> 52.5, lround(2.5) = 3 -> 53 (unlimited: 62.5).
  EXPECT_EQ(decide("hoomd_balance", obs({50}, {1.0, 1.5}, 100, 4)), B{53});
  EXPECT_EQ(decide("hoomd_balance", obs({50}, {1.5, 1.0}, 100, 4)), B{47});
  // P=3, T = {1, 1, 2}: scales 1.05, 1.05, 0.95 -> targets 31.5, 31.5, 28.5 (sum 91.5): the fit takes 0.5
  // off each width: 31, 31, 28 -> {31, 62}.
  EXPECT_EQ(decide("hoomd_balance", obs({30, 60}, {1, 1, 2}, 90, 4)), (B{31, 62}));
  // max_scale 0.2: targets 60 (1.25 limited to 1.2) and 41.67 (0.833, inside the limit), sum 101.67: the
  // fit takes 0.83 off each -> 59.17 -> 59.
  EXPECT_EQ(decide("hoomd_balance", obs({50}, {1.0, 1.5}, 100, 4), params({{"max_scale", "0.2"}})), B{59});
}

TEST(HoomdBalance, ToleranceIsStrict) {
  // max/mean = 1.04/1.02 = 1.0196 <= 1.02: no move; 1.05/1.025 = 1.0244: move (targets 51.25, 48.81 -> 51).
  EXPECT_EQ(decide("hoomd_balance", obs({50}, {1.0, 1.04}, 100, 4)), B{50});
  EXPECT_EQ(decide("hoomd_balance", obs({50}, {1.0, 1.05}, 100, 4)), B{51});
  EXPECT_EQ(decide("hoomd_balance", obs({50}, {1.0, 1.05}, 100, 4), params({{"tolerance", "1.03"}})), B{50});
}

TEST(HoomdBalance, HalfWayBoundRefitsTheOtherBoundaries) {
  // widths {50, 4, 46}, T = {2, 0, 0}: targets 47.5, 4.2, 48.3. Unbounded: 47.5, 51.7. Boundary 1 may not
  // go below mid(50, 54) = 52, so the fit sets it to 52 and re-fits boundary 0 to (47.5 + 52 - 4.2)/2 =
  // 47.65 -> 48 (the unbounded 47.5 would round to 47).
  EXPECT_EQ(decide("hoomd_balance", obs({50, 54}, {2, 0, 0}, 100, 2)), (B{48, 52}));
}

TEST(HoomdBalance, MaxIterationsRecountsTheMovedLoad) {
  // Pass 2 re-estimates the loads at 52.5 with the measured densities (1/50, 1.5/50): 1.075, 1.425; still
  // 1.14 > 1.02, so each slab scales by 5% again: 55.125, 45.125 (sum 100.25) -> 55.
  EXPECT_EQ(decide("hoomd_balance", obs({50}, {1.0, 1.5}, 100, 4), params({{"max_iterations", "2"}})), B{55});
}

// ----------------------------------------------------------------------------------------------- all_tensor
TEST(AllTensor, HandComputedTwoAndThreeRanks) {
  // P=2, widths 50/50, T = {1, 1.5}: gamma = max(4.1, 2 (1 + 1)) = 4.1;
  // shift = 0.5/4.1 * (1.5 - 1)/2.5 * 100 = 2.44 -> 52.
  EXPECT_EQ(decide("all_tensor", obs({50}, {1.0, 1.5}, 100, 4)), B{52});
  EXPECT_EQ(decide("all_tensor", obs({50}, {1.5, 1.0}, 100, 4)), B{48});
  // P=3, widths 20/40/40, T = {1, 2, 1}. Boundary 0: gamma = max(4.1, 2 (1 + 40/20)) = 6,
  // shift = 0.5/6 * 1/3 * 60 = 1.67 -> 22. Boundary 1: gamma 4.1, shift = 0.5/4.1 * (-1/3) * 80 = -3.25 -> 57.
  EXPECT_EQ(decide("all_tensor", obs({20, 60}, {1, 2, 1}, 100, 4)), (B{22, 57}));
  // gamma given overrides the formula: gamma 1 -> shift 0.5 * 0.2 * 100 = 10.
  EXPECT_EQ(decide("all_tensor", obs({50}, {1.0, 1.5}, 100, 4), params({{"gamma", "1"}})), B{60});
}

TEST(AllTensor, ShiftIsCappedAt049OfTheShrinkingSlabsSlack) {
  // widths 10/90, T = {0, 1}, gamma 1: shift 0.5 * 1 * 100 = 50 > 0.49 (90 - 4) = 42.14 -> 52.14 -> 52.
  EXPECT_EQ(decide("all_tensor", obs({10}, {0.0, 1.0}, 100, 4), params({{"gamma", "1"}})), B{52});
  // The slab at min_width cannot shrink at all: maxmove 0.49 (4 - 4) = 0.
  EXPECT_EQ(decide("all_tensor", obs({4}, {1.0, 0.0}, 100, 4), params({{"gamma", "1"}})), B{4});
}

TEST(AllTensor, NoThresholdButSubHalfSliceShiftsRoundToNothing) {
  // ALL has no switch-on threshold: T = {1, 1.01} gives 0.5/4.1 * 0.01/2.01 * 100 = 0.06 slices -> 0, while
  // the same ratio on 2000 slices gives 1.21 -> 1.
  EXPECT_EQ(decide("all_tensor", obs({50}, {1.0, 1.01}, 100, 4)), B{50});
  EXPECT_EQ(decide("all_tensor", obs({1000}, {1.0, 1.01}, 2000, 4)), B{1001});
}

// --------------------------------------------------------------------------------------------- lammps_shift
TEST(LammpsShift, HandComputedTwoRanks) {
  // Work 1 in slices 0-4, 3 in slices 5-9: slab sums 5 / 15, max/mean 1.5 > 1.05; target 10.
  // Bracket [5, 10] (sums 5, 20). Bisection: 7.5 (sum 12.5), 6.25 (8.75), 6.875 (10.625), 6.5625 (9.6875:
  // within 5% of 10, stop) -> round 6.5625 -> 7.
  const auto work = repeat({{5, 1.0}, {5, 3.0}});
  EXPECT_EQ(decide("lammps_shift", obs({5}, {5, 15}, 10, 1, work)), B{7});
  // Niter 1 stops after the first bisection: 7.5 -> 8 (half away from zero).
  EXPECT_EQ(decide("lammps_shift", obs({5}, {5, 15}, 10, 1, work), params({{"niter", "1"}})), B{8});
  // stopthresh 1.2: 7.5 is off by 25% -> 6.25 is off by 12.5% < 20%: stop -> 6.
  EXPECT_EQ(decide("lammps_shift", obs({5}, {5, 15}, 10, 1, work), params({{"stopthresh", "1.2"}})), B{6});
}

TEST(LammpsShift, HandComputedThreeRanks) {
  // 12 slices, work 1 in slices 0-5 and 4 in 6-11 (total 30, targets 10, 20); cuts {4, 8}: cumulative sums
  // 4, 14 -> slab work 4, 10, 16, max/mean 1.6. Cut 1 brackets [4, 8] (sums 4, 14), cut 2 [8, 12] (14, 30).
  // Iteration 1: 6 (sum 6), 10 (22). Iteration 2: 7 (10, exact), 9 (18). Iteration 3: cut 2 -> 9.5 (20,
  // exact): done. Rounding: 7, 9.5 -> 10 (half away from zero) -> slab work 10, 12, 8.
  const auto work = repeat({{6, 1.0}, {6, 4.0}});
  EXPECT_EQ(decide("lammps_shift", obs({4, 8}, {4, 10, 16}, 12, 1, work)), (B{7, 10}));
}

TEST(LammpsShift, ThresholdIsOnSlabWorkAndStrict) {
  // Slab work 5 / 5.2: max/mean 1.0196 <= 1.05 -> no move, whatever the measured times say.
  const auto work = repeat({{5, 1.0}, {5, 1.04}});
  EXPECT_EQ(decide("lammps_shift", obs({5}, {1.0, 3.0}, 10, 1, work)), B{5});
  EXPECT_EQ(decide("lammps_shift", obs({5}, {1.0, 3.0}, 10, 1, work), params({{"threshold", "1.01"}})), B{5});
}

TEST(LammpsShift, WeightTimeRescalesEachSlabsWorkToItsTime) {
  // Flat slice work (slab sums 5 / 5: balanced by count) but measured times 1 / 3: with weight=time the
  // slices weigh 0.2 and 0.6 (total 4, target 2): bisection 7.5 (sum 2.5), 6.25 (1.75), 6.875 (2.125),
  // 6.5625 (1.9375, within 5%) -> 7. Without weighting nothing moves.
  const auto work = repeat({{10, 1.0}});
  EXPECT_EQ(decide("lammps_shift", obs({5}, {1.0, 3.0}, 10, 1, work)), B{5});
  EXPECT_EQ(decide("lammps_shift", obs({5}, {1.0, 3.0}, 10, 1, work), params({{"weight", "time"}})), B{7});
  EXPECT_THROW(make_policy("lammps_shift", params({{"weight", "neigh"}})), InputError);
}

TEST(LammpsShift, MinWidthSweepSeparatesCoincidentCuts) {
  // All work in slice 10: both cuts converge into slice 10 (10.33, 10.67 -> 10, 11); the sweep keeps the
  // middle rank at min_width 3: {10, 13}.
  std::vector<double> work(20, 0.0);
  work[10] = 6.0;
  EXPECT_EQ(decide("lammps_shift", obs({7, 14}, {1, 1, 1}, 20, 3, work)), (B{10, 13}));
}

TEST(LammpsShift, NeedsSliceWork) {
  EXPECT_TRUE(policy_needs("lammps_shift").slice_work);
  EXPECT_FALSE(policy_needs("gromacs_dlb").slice_work);
  EXPECT_FALSE(policy_needs("hoomd_balance").slice_work);
  EXPECT_FALSE(policy_needs("all_tensor").slice_work);
  try {
    decide("lammps_shift", obs({5}, {1.0, 2.0}, 10, 1));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("slice_work"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------------- all four
TEST(ProductionBalancers, ZeroEqualAndFullyPackedCasesNeverMove) {
  const std::vector<double> zero(30, 0.0), flat(30, 1.0);
  for (const char* name : {"gromacs_dlb", "hoomd_balance", "all_tensor", "lammps_shift"}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(decide(name, obs({10, 20}, {0, 0, 0}, 30, 4, zero)), (B{10, 20}));
    EXPECT_EQ(decide(name, obs({10, 20}, {2, 2, 2}, 30, 4, flat)), (B{10, 20}));
    EXPECT_TRUE(decide(name, obs({}, {3.0}, 30, 4, flat)).empty());  // P = 1
    // P * min_width == slices: no room, nothing moves however unequal the load.
    std::vector<double> skew(12, 0.0);
    skew[5] = 9.0;
    EXPECT_EQ(decide(name, obs({4, 8}, {1, 50, 1}, 12, 4, skew)), (B{4, 8}));
  }
  // Latched-on gromacs_dlb with all-zero times: no NaN, no move.
  auto g = make_policy("gromacs_dlb");
  g->load_state({{"dlb_on", {1.0}}});
  EXPECT_EQ(g->decide(obs({10, 20}, {0, 0, 0}, 30, 4)), (B{10, 20}));
}

TEST(ProductionBalancers, ParameterRangesRefuseWorkTowardTheSlowerRank) {
  const std::vector<std::pair<const char*, std::pair<const char*, const char*>>> bad = {
      {"gromacs_dlb", {"relax", "0"}},
      {"gromacs_dlb", {"relax", "-0.5"}},
      {"gromacs_dlb", {"relax", "2"}},
      {"gromacs_dlb", {"cap", "0"}},
      {"gromacs_dlb", {"cap", "1"}},
      {"gromacs_dlb", {"threshold", "-0.01"}},
      {"gromacs_dlb", {"threshold", "1.5"}},
      {"hoomd_balance", {"max_scale", "0"}},
      {"hoomd_balance", {"max_scale", "1"}},
      {"hoomd_balance", {"tolerance", "-1"}},
      {"hoomd_balance", {"max_iterations", "0"}},
      {"hoomd_balance", {"max_iterations", "2.0"}},
      {"all_tensor", {"gamma", "0"}},
      {"all_tensor", {"gamma", "-4"}},
      {"all_tensor", {"gamma", "0.5"}},
      {"all_tensor", {"gamma", "nan"}},
      {"lammps_shift", {"stopthresh", "0.9"}},
      {"lammps_shift", {"niter", "0"}},
      {"lammps_shift", {"threshold", "-1"}},
      {"lammps_shift", {"bogus", "1"}},
  };
  for (const auto& [name, kv] : bad) {
    SCOPED_TRACE(std::string(name) + "." + kv.first + "=" + kv.second);
    try {
      make_policy(name, params({{kv.first, kv.second}}));
      FAIL();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(kv.first), std::string::npos) << e.what();
    }
  }
  // Edge values inside the ranges are accepted.
  EXPECT_NO_THROW(make_policy("gromacs_dlb", params({{"relax", "1.9"}, {"cap", "0.99"}, {"threshold", "0"}})));
  EXPECT_NO_THROW(make_policy("all_tensor", params({{"gamma", "1"}})));
  EXPECT_NO_THROW(make_policy("lammps_shift", params({{"stopthresh", "1"}, {"niter", "1"}})));
}
