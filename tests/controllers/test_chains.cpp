// Chains-on-chains and nearest-partition against brute force, plus degenerate inputs.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "controllers/chains.hpp"
#include "common/errors.hpp"
#include "controllers/partition.hpp"

using namespace semlb;

namespace {
// Calls visit(interior boundaries) for every partition of S slices into P parts of width >= min_width.
void for_each_partition(int S, int P, int min_width, const std::function<void(const std::vector<int>&)>& visit) {
  std::vector<int> b;
  std::function<void(int, int)> rec = [&](int start, int left) {
    if (left == 1) {
      if (S - start >= min_width) visit(b);
      return;
    }
    for (int e = start + min_width; e <= S - (left - 1) * min_width; ++e) {
      b.push_back(e);
      rec(e, left - 1);
      b.pop_back();
    }
  };
  rec(0, P);
}

double brute_force(const std::vector<double>& w, int ranks, int min_width) {
  double best = std::numeric_limits<double>::infinity();
  for_each_partition(static_cast<int>(w.size()), ranks, min_width,
                     [&](const std::vector<int>& b) { best = std::min(best, bottleneck(w, b)); });
  return best;
}

// Least migration from `current` over the partitions within `bound` (-1 when none).
long brute_nearest(const std::vector<double>& w, const std::vector<int>& current, int min_width, double bound) {
  long best = -1;
  for_each_partition(static_cast<int>(w.size()), static_cast<int>(current.size()) + 1, min_width,
                     [&](const std::vector<int>& b) {
                       if (bottleneck(w, b) > bound) return;
                       const long m = migration(current, b);
                       if (best < 0 || m < best) best = m;
                     });
  return best;
}

// Calls check(work, P, min_width) on every S <= 11, P <= 4, min_width <= 3 that fits, with several random
// work vectors each: all zeros first, then zeros mixed with clumps.
int for_each_small_case(const std::function<void(const std::vector<double>&, int, int)>& check) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  int cases = 0;
  for (int S = 1; S <= 11; ++S)
    for (int P = 1; P <= 4; ++P)
      for (int w = 1; w <= 3; ++w) {
        if (P * w > S) continue;
        for (int trial = 0; trial < 6; ++trial) {
          std::vector<double> work(S);
          for (auto& x : work) x = trial == 0 ? 0.0 : (u(rng) < 2.0 ? 0.0 : u(rng));
          check(work, P, w);
          ++cases;
        }
      }
  return cases;
}
}  // namespace

TEST(Chains, MatchesBruteForceOnSmallCases) {
  const int cases = for_each_small_case([](const std::vector<double>& work, int P, int w) {
    const auto b = optimal_partition(work, P, w);
    ASSERT_EQ(static_cast<int>(b.size()), P - 1);
    ASSERT_NO_THROW(check_partition(b, static_cast<int>(work.size()), w));
    ASSERT_DOUBLE_EQ(bottleneck(work, b), brute_force(work, P, w)) << "S=" << work.size() << " P=" << P << " w=" << w;
  });
  EXPECT_GT(cases, 400);
}

TEST(Chains, UniformWorkIsSplitEvenlyAndErrorsAreClear) {
  const std::vector<double> flat(12, 1.0);
  EXPECT_EQ(optimal_partition(flat, 3, 1), (std::vector<int>{4, 8}));
  const std::vector<double> spike{0, 0, 0, 100, 0, 0, 0, 0};
  EXPECT_DOUBLE_EQ(bottleneck(spike, optimal_partition(spike, 4, 2)), 100.0);
  EXPECT_THROW(optimal_partition(flat, 5, 3), InputError);
  EXPECT_THROW(optimal_partition(std::vector<double>{1, -1, 1}, 1, 1), InputError);
}

TEST(Chains, NearestPartitionMovesTheLeastWithinTheBound) {
  int slack = 0;  // bounds from the optimum to 50% above it, in turn
  const int cases = for_each_small_case([&](const std::vector<double>& work, int P, int w) {
    const int S = static_cast<int>(work.size());
    const auto current = uniform_partition(P, S);
    const double bound = bottleneck(work, optimal_partition(work, P, w)) * (1.0 + 0.1 * (slack++ % 6));
    const auto b = nearest_partition(work, current, w, bound);
    ASSERT_NO_THROW(check_partition(b, S, w));
    ASSERT_LE(bottleneck(work, b), bound * (1 + 1e-9));
    ASSERT_EQ(migration(current, b), brute_nearest(work, current, w, bound)) << "S=" << S << " P=" << P << " w=" << w;
  });
  EXPECT_GT(cases, 400);
}

TEST(Chains, NearestPartitionKeepsAPartitionAlreadyWithinTheBoundAndRefusesAnImpossibleOne) {
  const std::vector<double> work{1, 1, 1, 1, 1, 1, 1, 1};
  EXPECT_EQ(nearest_partition(work, std::vector<int>{3}, 1, 5.0), (std::vector<int>{3}));
  EXPECT_EQ(nearest_partition(work, std::vector<int>{2}, 1, 5.0), (std::vector<int>{3}));  // one slice, not two
  EXPECT_TRUE(nearest_partition(work, std::vector<int>{}, 1, 8.0).empty());                // one rank
  EXPECT_THROW(nearest_partition(work, std::vector<int>{4}, 1, 3.9), InputError);
  EXPECT_THROW(nearest_partition(work, std::vector<int>{}, 1, 7.0), InputError);
}
