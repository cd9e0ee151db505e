// The shipped GRU weights: they load, reproduce their recorded torch outputs (parity), and stay finite
// and valid over 2000-event rollouts. (First- vs last-quarter imbalance is reported by controller_long.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "controllers/gru.hpp"
#include "common/errors.hpp"
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
  EXPECT_EQ(h5::File::open_read(path).read_int_attr("steps"), 3000);  // surrogate/train/engine_mixed.yaml
  EXPECT_EQ(w.features, FeatureSet::v2);
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

// Every shipped weights file (the default and those trained with other migration penalties, experiments/frontier.yaml)
// loads by its bare name from any folder, reproduces its parity record, and drives the same rollout as its full
// path; a bare name that is shipped nowhere stays a missing file (InputError).
TEST(ShippedWeights, EveryShippedFileLoadsByItsBareName) {
  const auto folder = std::filesystem::path(default_gru_weights_path()).parent_path();
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".h5") continue;
    ++files;
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(std::filesystem::path(resolve_gru_weights(name)), entry.path()) << name;
    EXPECT_LT(gru_parity_error(entry.path().string()), 1e-5) << name;
    PolicyParams by_name, by_path;
    by_name.set("weights", name);
    by_path.set("weights", entry.path().string());
    auto a = make_policy("gru", by_name), b = make_policy("gru", by_path);
    const auto ra = surrogate::rollout(surrogate::make_scenario(9011, 4), *a, 100);
    const auto rb = surrogate::rollout(surrogate::make_scenario(9011, 4), *b, 100);
    EXPECT_EQ(ra.imbalance, rb.imbalance) << name;
    EXPECT_EQ(ra.migration, rb.migration) << name;
  }
  EXPECT_GE(files, 1);
  EXPECT_EQ(resolve_gru_weights("no_such_weights.h5"), "no_such_weights.h5");
  PolicyParams missing;
  missing.set("weights", "no_such_weights.h5");
  EXPECT_THROW(make_policy("gru", missing), InputError);
}
