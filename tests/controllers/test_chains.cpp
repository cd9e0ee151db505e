// Chains-on-chains partitioning against brute force, plus degenerate inputs.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "controllers/chains.hpp"
#include "controllers/errors.hpp"
#include "controllers/partition.hpp"

using namespace semlb;

namespace {
double brute_force(const std::vector<double>& w, int ranks, int min_width) {
  const int S = static_cast<int>(w.size());
  double best = std::numeric_limits<double>::infinity();
  std::vector<int> b;
  std::function<void(int, int)> rec = [&](int start, int left) {
    if (left == 1) {
      if (S - start < min_width) return;
      b.push_back(S);
      double worst = 0, sum = 0;
      int from = 0;
      for (int e : b) {
        sum = 0;
        for (int s = from; s < e; ++s) sum += w[s];
        worst = std::max(worst, sum);
        from = e;
      }
      best = std::min(best, worst);
      b.pop_back();
      return;
    }
    for (int e = start + min_width; e <= S - (left - 1) * min_width; ++e) {
      b.push_back(e);
      rec(e, left - 1);
      b.pop_back();
    }
  };
  rec(0, ranks);
  return best;
}
}  // namespace

TEST(Chains, MatchesBruteForceOnSmallCases) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  int cases = 0;
  for (int S = 1; S <= 11; ++S)
    for (int P = 1; P <= 4; ++P)
      for (int w = 1; w <= 3; ++w) {
        if (P * w > S) continue;
        for (int trial = 0; trial < 6; ++trial) {
          std::vector<double> work(S);
          for (auto& x : work) x = trial == 0 ? 0.0 : (u(rng) < 2.0 ? 0.0 : u(rng));  // zeros and clumps
          const auto b = optimal_partition(work, P, w);
          ASSERT_EQ(static_cast<int>(b.size()), P - 1);
          ASSERT_NO_THROW(check_partition(b, S, w));
          ASSERT_DOUBLE_EQ(bottleneck(work, b), brute_force(work, P, w)) << "S=" << S << " P=" << P << " w=" << w;
          ++cases;
        }
      }
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
