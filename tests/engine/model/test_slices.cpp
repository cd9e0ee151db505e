// The bin grid of model/slices.hpp: bins of at least the cutoff, never more than Grid::kMaxBins.
#include <gtest/gtest.h>

#include <array>
#include <utility>

#include "engine/model/slices.hpp"

namespace semlb::engine {
namespace {

// A box of more bins than Grid::kMaxBins (2^24), even 2e15 along one axis (2e9 um in bins of 1e-6 um) or an element
// at 1e300 um, gets fewer, larger bins: never an int overflow, every bin edge still >= the cutoff.
TEST(Slices, BinCountsStayWithinThirtyTwoBitsWithBinsOfAtLeastTheCutoff) {
  const std::array<double, 3> o{0, 0, 0};
  for (const auto& [hi, cutoff] : {std::pair{std::array<double, 3>{2e9, 2e9, 2e9}, 1e-6},
                                   {{1e300, 10, 10}, 8.75},
                                   {{2e3, 2e3, 2e3}, 1.0},
                                   {{1e9, 1, 1}, 1e-3}}) {
    const Grid g = Grid::cover(o, hi, cutoff);
    EXPECT_LE(g.bins(), Grid::kMaxBins) << hi[0] << " / " << cutoff;
    for (int d = 0; d < 3; ++d) {
      EXPECT_GE(g.dims[d], 1);
      EXPECT_GE(g.size[d], cutoff) << d;
      EXPECT_GE(g.size[d] * g.dims[d], hi[d] * (1 - 1e-12)) << d;
    }
  }
  EXPECT_EQ(Grid::cover(o, {200, 200, 200}, 1.0).bins(), 199L * 199 * 199);  // below the limit: bins of the cutoff
}

}  // namespace
}  // namespace semlb::engine
