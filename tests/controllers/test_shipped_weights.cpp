// The shipped GRU weights: they load, reproduce their recorded torch outputs (parity), and stay finite
// and valid over 2000-event rollouts. (First- vs last-quarter imbalance is reported by controller_long.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "controllers/gru.hpp"
#include "common/h5.hpp"
#include "controllers/policy.hpp"
#include "surrogate/rollout.hpp"

using namespace semlb;

TEST(ShippedWeights, LoadAndReproduceTheirParityRecord) {
  const auto path = default_gru_weights_path();
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing: run `make train`";
  const auto w = load_gru_weights(path);
  EXPECT_EQ(w.hidden, 24);
  EXPECT_EQ(w.parameter_count(), 2761);
  EXPECT_FALSE(w.head_w.isZero());
  EXPECT_LT(gru_parity_error(path), 1e-5);
  EXPECT_EQ(h5::File::open_read(path).read_int_attr("steps"), 6000);
}

TEST(ShippedWeights, LongRolloutsStayFiniteAndValid) {
  // 40x the training horizon; the rollout itself rejects any invalid partition the policy returns.
  for (int ranks : {2, 4, 8, 16}) {
    auto gru = make_policy("gru");
    const auto r = surrogate::rollout(surrogate::make_scenario(9007, ranks), *gru, 2000);
    for (double v : r.imbalance) ASSERT_TRUE(std::isfinite(v)) << "P " << ranks;
    EXPECT_GT(r.migration, 0) << "P " << ranks;
  }
}
