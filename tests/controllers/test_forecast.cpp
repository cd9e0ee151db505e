// Holt forecaster on constant and linear series; persistence/holt/oracle policies repartition their input.
#include <gtest/gtest.h>

#include "controllers/chains.hpp"
#include "common/errors.hpp"
#include "controllers/forecast.hpp"
#include "controllers/policy.hpp"

using namespace semlb;

TEST(Holt, ConstantSeriesForecastsTheConstant) {
  HoltForecaster h(0.3, 0.2);
  std::vector<double> f;
  for (int t = 0; t < 50; ++t) f = h.update(std::vector<double>{2.5, 0.0});
  EXPECT_DOUBLE_EQ(f[0], 2.5);
  EXPECT_DOUBLE_EQ(f[1], 0.0);
}

TEST(Holt, LinearSeriesIsForecastOneStepAhead) {
  HoltForecaster exact(1.0, 1.0);  // level = y_t, trend = y_t - y_{t-1}: exact after two points
  HoltForecaster smooth(0.5, 0.3);
  std::vector<double> fe, fs;
  for (int t = 0; t < 300; ++t) {
    const std::vector<double> y{1.0 + 0.5 * t};
    fe = exact.update(y);
    fs = smooth.update(y);
  }
  EXPECT_DOUBLE_EQ(fe[0], 1.0 + 0.5 * 300);
  EXPECT_NEAR(fs[0], 1.0 + 0.5 * 300, 1e-9);
}

TEST(Holt, ForecastNeverNegativeAndParametersChecked) {
  HoltForecaster h(1.0, 1.0);
  h.update(std::vector<double>{10.0});
  EXPECT_EQ(h.update(std::vector<double>{1.0})[0], 0.0);  // 1 + (1 - 10) clipped at 0
  EXPECT_THROW(HoltForecaster(0.0, 0.1), InputError);
  EXPECT_THROW(HoltForecaster(0.5, 1.5), InputError);
}

namespace {
Observation two_ranks_of_four_slices() {
  Observation o;
  o.slices = 8;
  o.min_width = 1;
  o.boundaries = {4};
  o.times = {1.0, 1.0};
  return o;
}
}  // namespace

TEST(RepartitionPolicies, UseTheirInputAndNeedIt) {
  Observation o = two_ranks_of_four_slices();
  o.slice_work = {1, 1, 1, 1, 1, 1, 6, 0};
  o.oracle_work = {6, 0, 1, 1, 1, 1, 1, 1};
  EXPECT_EQ(make_policy("persistence")->decide(o), optimal_partition(o.slice_work, 2, 1));
  EXPECT_EQ(make_policy("holt")->decide(o), optimal_partition(o.slice_work, 2, 1));  // first event: level = y
  EXPECT_EQ(make_policy("oracle")->decide(o), optimal_partition(o.oracle_work, 2, 1));
  o.slice_work.clear();
  o.oracle_work.clear();
  EXPECT_THROW(make_policy("persistence")->decide(o), InputError);
  EXPECT_THROW(make_policy("oracle")->decide(o), InputError);
}

TEST(RepartitionPolicies, LazyOracleWaitsUntilTheTrueImbalanceExceedsTauThenMovesTheLeast) {
  Observation o = two_ranks_of_four_slices();
  o.oracle_work = {1, 1, 1, 1, 1, 1, 1, 1.5};  // imbalance (4.5 - 4) / 4.25 = 0.118 on the current split
  PolicyParams lenient(std::map<std::string, std::string>{{"tau", "0.2"}});
  EXPECT_EQ(make_policy("lazy_oracle", lenient)->decide(o), o.boundaries);
  PolicyParams strict(std::map<std::string, std::string>{{"tau", "0.1"}});
  EXPECT_EQ(make_policy("lazy_oracle", strict)->decide(o), (std::vector<int>{4}));  // 4 | 4.5 is already optimal
  o.oracle_work = {1, 1, 1, 1, 1, 1, 3, 3};                                         // optimum 6 | 6: boundary 4 -> 6
  EXPECT_EQ(make_policy("lazy_oracle", strict)->decide(o), (std::vector<int>{6}));
  PolicyParams slack({{"tau", "0.1"}, {"slack", "0.2"}});  // bound 7.2: boundary 5 (5 | 7) is nearer
  EXPECT_EQ(make_policy("lazy_oracle", slack)->decide(o), (std::vector<int>{5}));
  o.oracle_work.clear();
  EXPECT_THROW(make_policy("lazy_oracle")->decide(o), InputError);
}
