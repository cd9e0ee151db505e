// run/bench.hpp: the tissue statistics `semlb bench engine` prints beside its times.
#include <gtest/gtest.h>
#include <omp.h>

#include "../engine_fixtures.hpp"
#include "engine/model/slices.hpp"
#include "engine/run/bench.hpp"

namespace semlb::engine {
namespace {

// The mean count of other elements within `cutoff` of every stride-th element (0, stride, ...), by brute force.
double mean_neighbours(const State& s, double cutoff, long stride = 1) {
  long count = 0, sampled = 0;
  for (long e = 0; e < s.elements(); e += stride, ++sampled)
    for (long o = 0; o < s.elements(); ++o) {
      double r2 = 0;
      for (int d = 0; d < 3; ++d) r2 += std::pow(s.position[3 * e + d] - s.position[3 * o + d], 2);
      count += o != e && r2 < cutoff * cutoff;
    }
  return static_cast<double>(count) / static_cast<double>(sampled);
}

TEST(TissueStats, NeighboursOfAFullSampleAreTheBruteForceMeanOnAnyThreadCount) {
  const State s = testing::random_state(300, 4, 30.0, 7);
  const double cutoff = 4.0;
  const Grid g = Grid::cover({0, 0, 0}, {30, 30, 30}, cutoff);
  const double want = mean_neighbours(s, cutoff);
  ASSERT_GT(want, 1.0);  // the tissue is dense enough that a wrong count shows
  const int threads = omp_get_max_threads();
  for (int n : {1, 4}) {
    omp_set_num_threads(n);
    const TissueStats t = tissue_stats(s, g, cutoff, s.elements());
    EXPECT_DOUBLE_EQ(t.neighbours, want) << n << " threads";
  }
  omp_set_num_threads(threads);
}

TEST(TissueStats, ASparseSampleTakesEveryStrideThElement) {
  const State s = testing::random_state(300, 4, 30.0, 11);
  const double cutoff = 4.0;
  const Grid g = Grid::cover({0, 0, 0}, {30, 30, 30}, cutoff);
  // sample 10 of 1200: elements 0, 120, ..., 1080
  ASSERT_EQ(s.elements(), 1200);
  EXPECT_DOUBLE_EQ(tissue_stats(s, g, cutoff, 10).neighbours, mean_neighbours(s, cutoff, 120));
}

}  // namespace
}  // namespace semlb::engine
