// GRU controller: the cell against hand-written equations, residual clipping, zero head == reactive,
// long rollouts stay bounded, and the HDF5 weights format (round trip and refusals).
#include <gtest/gtest.h>

#include "../run_command.hpp"

#include <cmath>
#include <filesystem>
#include <random>

#include "common/errors.hpp"
#include "controllers/features.hpp"
#include "controllers/gru.hpp"
#include "common/h5.hpp"
#include "controllers/partition.hpp"
#include "controllers/policy.hpp"

using namespace semlb;
namespace fs = std::filesystem;

namespace {

std::string temp_file(const std::string& name) { return semlb::test::fresh_dir("gru_" + name) + "/" + name; }

std::string write_weights(const GruWeights& w, const std::string& name) {
  const auto path = temp_file(name);
  save_gru_weights(path, w);
  return path;
}

std::unique_ptr<Policy> gru_policy(const std::string& path) {
  PolicyParams p;
  p.set("weights", path);
  return make_policy("gru", p);
}

// A stream of random valid observations for P ranks (boundaries taken from the decisions).
struct Stream {
  std::mt19937 rng{11};
  Observation next(const std::vector<int>& b, int slices, int min_width, int event) {
    std::uniform_real_distribution<double> u(0.5, 1.5);
    Observation o;
    o.event = event;
    o.slices = slices;
    o.min_width = min_width;
    o.boundaries = b;
    for (size_t r = 0; r <= b.size(); ++r) o.times.push_back(u(rng));
    o.growth_phase = (event % 17) / 17.0;
    o.growth_event = event % 17 == 0;
    return o;
  }
};

}  // namespace

TEST(Gru, StepMatchesTheGruEquations) {
  GruWeights w = GruWeights::random_zero_head(2, 3, 5);
  const Eigen::VectorXd x = Eigen::Vector3d(0.3, -0.7, 1.1), h = Eigen::Vector2d(0.2, -0.4);
  const Eigen::VectorXd out = gru_step(w, x, h);
  auto sig = [](double v) { return 1 / (1 + std::exp(-v)); };
  for (int j = 0; j < 2; ++j) {
    auto gi = [&](int g) { return w.w_ih.row(g * 2 + j).dot(x) + w.b_ih(g * 2 + j); };
    auto gh = [&](int g) { return w.w_hh.row(g * 2 + j).dot(h) + w.b_hh(g * 2 + j); };
    const double r = sig(gi(0) + gh(0)), z = sig(gi(1) + gh(1)), n = std::tanh(gi(2) + r * gh(2));
    EXPECT_NEAR(out(j), (1 - z) * n + z * h(j), 1e-15);
  }
  EXPECT_EQ(w.parameter_count(), 3 * (2 * 3 + 2 * 2 + 2 * 2) + 2 + 1);
  EXPECT_EQ(GruWeights::random_zero_head(24, kFeatureCount, 1).parameter_count(), 2761);  // paper: ~2.8e3
}

TEST(Gru, ResidualMagnitudeClipsAtanhAndStaysBounded) {
  EXPECT_EQ(residual_magnitude(3.0, 10.0, 0.0), 3.0);          // zero residual: exact identity
  EXPECT_EQ(residual_magnitude(30.0, 10.0, 0.0), 10.0);        // proposal beyond the bound is clipped
  const double clipped = residual_magnitude(30.0, 10.0, 0.1);  // atanh(1 - 1e-6) finite, result <= bound
  EXPECT_TRUE(std::isfinite(clipped));
  EXPECT_LE(clipped, 10.0);
  EXPECT_GT(clipped, 9.99);
  EXPECT_LE(residual_magnitude(3.0, 10.0, 50.0), 10.0);
  EXPECT_EQ(residual_magnitude(3.0, 10.0, -50.0), 0.0);  // never reverses direction
  EXPECT_NEAR(residual_magnitude(3.0, 10.0, 0.2), 10.0 * std::tanh(std::atanh(0.3) + 0.2), 1e-12);
  EXPECT_EQ(residual_magnitude(3.0, 0.0, 0.2), 0.0);
}

TEST(Gru, ZeroHeadReproducesReactiveOver400Events) {
  const auto path = write_weights(GruWeights::random_zero_head(24, kFeatureCount, 3), "zero_head.h5");
  for (int P : {2, 5, 16}) {
    auto gru = gru_policy(path);
    auto reactive = make_policy("reactive");
    Stream stream;
    const int slices = 40 * P, min_width = 3;
    std::vector<int> b;
    for (int r = 1; r < P; ++r) b.push_back(r * slices / P);
    for (int t = 0; t < 400; ++t) {
      const Observation o = stream.next(b, slices, min_width, t);
      const auto expected = reactive->decide(o);
      ASSERT_EQ(gru->decide(o), expected) << "P=" << P << " event " << t;
      b = expected;
    }
  }
  fs::remove(path);
}

TEST(Gru, NonZeroHeadChangesDecisionsAndStaysFiniteOver2000Events) {
  GruWeights w = GruWeights::random_zero_head(24, kFeatureCount, 4);
  w.head_w.setConstant(0.8);
  w.head_b = -0.3;
  const auto path = write_weights(w, "head.h5");
  auto gru = gru_policy(path);
  auto reactive = make_policy("reactive");
  Stream stream;
  std::vector<int> b{100, 200, 300};
  int differ = 0;
  for (int t = 0; t < 2000; ++t) {
    const Observation o = stream.next(b, 400, 4, t);
    const auto next = gru->decide(o);
    differ += next != reactive->decide(o);
    ASSERT_NO_THROW(check_partition(next, 400, 4));
    b = next;
  }
  EXPECT_GT(differ, 100);
  fs::remove(path);
}

TEST(GruWeightsFile, RoundTripsExactly) {
  GruWeights w = GruWeights::random_zero_head(24, kFeatureCount, 9);
  w.head_w.setLinSpaced(-1, 1);
  w.head_b = 0.25;
  w.ds_max_frac = 0.4;
  const auto path = write_weights(w, "roundtrip.h5");
  const GruWeights r = load_gru_weights(path);
  EXPECT_EQ(r.w_ih, w.w_ih);
  EXPECT_EQ(r.w_hh, w.w_hh);
  EXPECT_EQ(r.b_ih, w.b_ih);
  EXPECT_EQ(r.b_hh, w.b_hh);
  EXPECT_EQ(r.head_w, w.head_w);
  EXPECT_EQ(r.head_b, 0.25);
  EXPECT_EQ(r.ds_max_frac, 0.4);
  fs::remove(path);
}

namespace {
// Writes a weights file, lets `mutate` damage it, and returns the loader's error message.
std::string refusal(const std::function<void(h5::File&)>& mutate, bool skip_weight_hh = false) {
  const auto path = temp_file("bad.h5");
  const GruWeights w = GruWeights::random_zero_head(24, kFeatureCount, 2);
  {
    auto f = h5::File::create(path);
    f.write_attr("format", std::string("semlb-gru"));
    f.write_attr("version", kGruFormatVersion);
    f.write_attr("feature_set", std::string(kFeatureSet));
    f.write_attr("features", feature_list());
    f.write_attr("hidden", 24L);
    f.write_attr("ds_max_frac", 0.5);
    f.write("/gru/weight_ih", {72, 12}, std::vector<double>(72 * 12, 0.1));
    if (!skip_weight_hh) f.write("/gru/weight_hh", {72, 24}, std::vector<double>(72 * 24, 0.1));
    f.write("/gru/bias_ih", {72}, std::vector<double>(72, 0.0));
    f.write("/gru/bias_hh", {72}, std::vector<double>(72, 0.0));
    f.write("/head/bias", {1}, std::vector<double>{0.0});
    mutate(f);
  }
  try {
    load_gru_weights(path);
  } catch (const InputError& e) {
    fs::remove(path);
    return e.what();
  }
  fs::remove(path);
  return "";
}
}  // namespace

TEST(GruWeightsFile, RefusesWrongShapesVersionsFeaturesAndMissingData) {
  const auto head = [](h5::File& f) { f.write("/head/weight", {1, 24}, std::vector<double>(24, 0.0)); };
  EXPECT_EQ(refusal(head), "");  // the well-formed file loads
  EXPECT_NE(refusal([](h5::File& f) {
              f.write("/head/weight", {1, 20}, std::vector<double>(20, 0.0));
            }).find("/head/weight has shape 1x20, expected 1x24"),
            std::string::npos);
  EXPECT_NE(refusal(head, true).find("dataset /gru/weight_hh is missing"), std::string::npos);
  EXPECT_NE(refusal([](h5::File&) {}).find("/head/weight is missing"), std::string::npos);
  EXPECT_NE(refusal([](h5::File& f) {
              f.write("/head/weight", {1, 24}, std::vector<double>(24, NAN));
            }).find("non-finite"),
            std::string::npos);
  const auto path = temp_file("version.h5");
  {
    auto f = h5::File::create(path);
    f.write_attr("format", std::string("semlb-gru"));
    f.write_attr("version", 99L);
  }
  try {
    load_gru_weights(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'version' is 99"), std::string::npos) << e.what();
  }
  {
    auto f = h5::File::create(path);
    f.write_attr("format", std::string("semlb-gru"));
    f.write_attr("version", kGruFormatVersion);
    f.write_attr("feature_set", std::string(kFeatureSet));
    f.write_attr("features", std::string("local_imbalance,width_left"));
  }
  EXPECT_THROW(load_gru_weights(path), InputError);
  EXPECT_THROW(load_gru_weights(temp_file("does_not_exist.h5")), InputError);
  fs::remove(path);
}

TEST(Features, AreClampedAndDimensionless) {
  BoundaryState s;
  s.local_imbalance = 1.9;
  s.prev_local_imbalance = -1.9;
  s.global_imbalance = 7;
  s.width_left = 1000;
  s.width_right = 3;
  s.min_width = 3;
  s.mean_width = 10;
  s.last_move = -40;
  s.proposal = 5;
  s.ds_max = 2.5;
  s.growth_phase = 0.25;
  s.growth_event = true;
  const auto f = boundary_features(s);
  const FeatureVector expected{1, 1, 2, 4, 0.3, 4, 0, -1, 1, std::cos(M_PI / 2), 1, 1};
  for (int i = 0; i < kFeatureCount; ++i) EXPECT_NEAR(f[i], expected[i], 1e-12) << feature_names()[i];
}

// boundary-v2 squashes where v1 clamps: equal to first order at small values, distinct (never flat) at engine values.
TEST(Features, SetV2SquashesTheImbalancesAndTheLastMoveInsteadOfClamping) {
  BoundaryState s;
  s.local_imbalance = 3.0;  // engine workloads: |I_t| up to ~1 and beyond
  s.prev_local_imbalance = 1.0;
  s.global_imbalance = 4.0;
  s.mean_width = 10;
  s.width_left = s.width_right = 10;
  s.last_move = 10;  // 4 quarter-widths
  s.ds_max = 1;
  const auto v1 = boundary_features(s, FeatureSet::v1), v2 = boundary_features(s, FeatureSet::v2);
  EXPECT_EQ(v1[0], 1.0);
  EXPECT_DOUBLE_EQ(v2[0], 0.75);       // 3 / (1 + 3)
  EXPECT_DOUBLE_EQ(v2[1], 2.0 / 3.0);  // change 2
  EXPECT_EQ(v1[2], 2.0);
  EXPECT_DOUBLE_EQ(v2[2], 0.8);  // 4 / (1 + 4)
  EXPECT_DOUBLE_EQ(v2[7], 0.8);  // last move 4 quarter-widths
  for (int i : {3, 4, 5, 6, 8, 9, 10, 11}) EXPECT_EQ(v1[i], v2[i]) << feature_names()[i];
  s.local_imbalance = 2.5;  // v1 cannot tell 2.5 from 3; v2 can
  EXPECT_EQ(boundary_features(s, FeatureSet::v1)[0], v1[0]);
  EXPECT_LT(boundary_features(s, FeatureSet::v2)[0], v2[0]);
  s.local_imbalance = 1e-3;
  EXPECT_NEAR(boundary_features(s, FeatureSet::v2)[0], 1e-3, 1e-6);
  EXPECT_THROW(parse_feature_set("boundary-v3", "x: "), InputError);
}

// A weights file names its feature set; a v2 file loads as v2, and with a zero head it is still reactive.
TEST(GruWeightsFile, CarriesItsFeatureSet) {
  GruWeights w = GruWeights::random_zero_head(24, kFeatureCount, 3);
  w.features = FeatureSet::v2;
  const auto path = write_weights(w, "v2.h5");
  EXPECT_EQ(load_gru_weights(path).features, FeatureSet::v2);
  EXPECT_EQ(h5::File::open_read(path).read_text_attr("feature_set"), "boundary-v2");
  auto gru = gru_policy(path);
  auto reactive = make_policy("reactive");
  Stream stream;
  std::vector<int> b = {20, 40, 60};
  for (int t = 0; t < 100; ++t) {
    const Observation o = stream.next(b, 80, 3, t);
    const auto expected = reactive->decide(o);
    ASSERT_EQ(gru->decide(o), expected) << "event " << t;
    b = expected;
  }
  fs::remove(path);
}
