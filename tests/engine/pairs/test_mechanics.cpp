// The mechanics pair term (pairs/mechanics.h): the Morse law by hand, its sets by cell and type pair, its errors.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/pairs/pair_term.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

using testing::pair_force_x;

const char* kSets =
    "{intra: {U0: 2.86, V0: 1, xi1: 1, xi2: 2}, inter: {U0: 2.86, V0: 0.5, xi1: 1, xi2: 2}, "
    "pairs: {basal-granular: {V0: 0.25}}}";

TEST(Mechanics, MorseForceByHandVanishesAtTheDocumentedEquilibrium) {
  const PairForces f = testing::pair_forces("mechanics", kSets, 8.75);
  const auto morse = [](double r, double V0) { return 2.86 * std::exp(-r) - V0 / 2 * std::exp(-r / 2); };
  // r* = ln(U0 xi2 / (V0 xi1)) / (1/xi1 - 1/xi2) = 2 ln(5.72) = 3.488 um for the intra set.
  const double r_star = std::log(2.86 * 2.0 / 1.0) / (1.0 - 0.5);
  const int a = phys64::semlb_info_pack(0, 0), b = phys64::semlb_info_pack(1, 0),
            granular = phys64::semlb_info_pack(2, 2);
  EXPECT_NEAR(pair_force_x(f, r_star, a, a), 0.0, 1e-9);
  EXPECT_GT(pair_force_x(f, r_star - 0.5, a, a), 0.0);  // repulsive inside
  EXPECT_LT(pair_force_x(f, r_star + 0.5, a, a), 0.0);  // adhesive outside
  for (const double r : {0.5, 2.0, 5.0, 8.0}) {
    EXPECT_NEAR(pair_force_x(f, r, a, a), morse(r, 1.0), 1e-9) << r;          // intra: the same cell
    EXPECT_NEAR(pair_force_x(f, r, a, b), morse(r, 0.5), 1e-9) << r;          // inter, basal-basal
    EXPECT_NEAR(pair_force_x(f, r, a, granular), morse(r, 0.25), 1e-9) << r;  // the pair's own set, both ways
    EXPECT_NEAR(pair_force_x(f, r, granular, a), morse(r, 0.25), 1e-9) << r;
  }
  EXPECT_EQ(pair_force_x(f, 8.75, a, a), 0.0);  // at the cutoff: no force
  // Coincident: |F| = f(0) = U0/xi1 - V0/xi2 = 2.36 for the intra set.
  int64_t acc[4];
  EXPECT_NEAR(testing::coincident_kick(PairTerms::at("mechanics").f64, f.params, f.cutoff * f.cutoff, a, 100, 101, acc),
              2.86 - 0.5, 1e-6);
}

TEST(Mechanics, BadSectionsNameTheField) {
  testing::expect_errors_name_fields(
      {{"effects.mechanics={intra: {xi1: 0}}", "effects.mechanics.intra.xi1"},
       {"effects.mechanics={inter: {U0: -1}}", "effects.mechanics.inter.U0"},
       {"effects.mechanics={pairs: {basal-nope: {V0: 1}}}", "effects.mechanics.pairs.basal-nope"},
       {"effects.mechanics={intra: {U1: 1}}", "effects.mechanics.intra.U1"}});
}

}  // namespace
}  // namespace semlb::engine
