// learned_repartition: its base rule, each learned part on a hand case, its state, and its weights file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "common/errors.hpp"
#include "common/h5.hpp"
#include "controllers/balancer.hpp"
#include "controllers/learned_repartition.hpp"
#include "controllers/partition.hpp"
#include "controllers/policy.hpp"
#include "surrogate/rollout.hpp"
#include "surrogate/scenario.hpp"
#include "../run_command.hpp"

using namespace semlb;

namespace {

Observation observe(const std::vector<int>& b, const std::vector<double>& work, const std::vector<double>& cost) {
  Observation o;
  o.slices = static_cast<int>(work.size());
  o.min_width = 1;
  o.boundaries = b;
  o.times = rank_sums(cost, b);
  double t = 0, w = 0;
  for (double x : o.times) t += x;
  for (double x : work) w += x;
  o.slice_work = work;
  for (double& x : o.slice_work) x *= t / w;
  return o;
}

PolicyParams params(std::initializer_list<std::pair<const char*, const char*>> kv) {
  PolicyParams p;
  p.set("weights", "none");
  for (const auto& [k, v] : kv) p.set(k, v);
  return p;
}

}  // namespace

TEST(Partition, EqualShareTargetsCutWhereTheCumulativeWorkSplitsEvenly) {
  EXPECT_EQ(equal_share_targets(std::vector<double>{1, 1, 1, 1}, 2), std::vector<double>{2.0});
  EXPECT_EQ(equal_share_targets(std::vector<double>{0, 4, 0, 0}, 2), std::vector<double>{1.5});
  EXPECT_EQ(equal_share_targets(std::vector<double>{1, 1, 1, 1, 1, 1}, 3), (std::vector<double>{2.0, 4.0}));
  EXPECT_EQ(equal_share_targets(std::vector<double>{0, 0, 0, 0}, 4), (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_TRUE(equal_share_targets(std::vector<double>{1, 2}, 1).empty());
}

// All-zero parameters are the base rule: persistence with cut=quantile, decision for decision, on 400-event rollouts.
TEST(LearnedRepartition, ZeroParametersAreTheQuantileCutExactly) {
  PolicyParams quantile;
  quantile.set("cut", "quantile");
  for (int P : {2, 4, 8, 16}) {
    const auto s = surrogate::make_scenario(9012, P);
    auto learned = make_policy("learned_repartition", params({}));
    auto base = make_policy("persistence", quantile);
    const auto a = surrogate::rollout(s, *learned, 400, true), b = surrogate::rollout(s, *base, 400, true);
    ASSERT_EQ(a.migration, b.migration) << "P " << P;
    EXPECT_GT(a.migration, 0) << "P " << P;
    for (int t = 0; t < 400; ++t) ASSERT_EQ(*a.trace[t].decision, *b.trace[t].decision) << "P " << P << " t " << t;
  }
}

// The upper half costs twice what W_s says: the base rule keeps the cut at 50 (times 50 and 100); the correction
// moves it to where the measured times balance, 62.5 (rank 0: 50 + 2 x 12.5 = 75; rank 1: 2 x 37.5 = 75).
TEST(LearnedRepartition, TheCorrectionLearnsWhereWsMisjudgesTheTime) {
  const std::vector<double> work(100, 1.0);
  std::vector<double> cost(100, 1.0);
  for (int s = 50; s < 100; ++s) cost[s] = 2.0;
  for (const char* gain : {"0", "0.5"}) {
    auto p = make_policy("learned_repartition", params({{"gain", gain}}));
    std::vector<int> b{50};
    for (int t = 0; t < 40; ++t) b = p->decide(observe(b, work, cost));
    if (std::string(gain) == "0")
      EXPECT_EQ(b, std::vector<int>{50});
    else
      EXPECT_NEAR(b[0], 62.5, 1.0);
  }
  // A gap within the noise floor is left alone: the gaps at 50 are log(50 / 75) = -0.41 and log(100 / 75) = 0.29, so
  // a floor of 0.42 keeps the cut, and one of 0.25 makes the lower slices cheaper and the upper dearer: it moves up.
  for (const char* floor : {"0.42", "0.25"}) {
    auto p = make_policy("learned_repartition", params({{"gain", "0.5"}, {"noise_floor", floor}}));
    const auto b = p->decide(observe({50}, work, cost));
    if (std::string(floor) == "0.42")
      EXPECT_EQ(b, std::vector<int>{50});
    else
      EXPECT_GT(b[0], 50);
  }
}

// A move of 4 slices that lowers the predicted bottleneck by 4.8 (of a total 110 over 100 slices) is taken when
// it costs move_cost x 1.1 x 4 < 4.8 (move_cost 1.0: 4.4) and refused at move_cost 1.2 (5.28); a deadband of
// 0.05 (5 of the 100 slices) keeps the 4.17-slice target where it is, one of 0.04 (4 slices) does not.
TEST(LearnedRepartition, AMoveIsTakenWhenItsGainPaysForItsMigration) {
  std::vector<double> work(100, 1.0);
  for (int s = 50; s < 100; ++s) work[s] = 1.2;
  const auto o = observe({50}, work, work);
  EXPECT_EQ(make_policy("learned_repartition", params({}))->decide(o), std::vector<int>{54});
  EXPECT_EQ(make_policy("learned_repartition", params({{"move_cost", "1.0"}}))->decide(o), std::vector<int>{54});
  EXPECT_EQ(make_policy("learned_repartition", params({{"move_cost", "1.2"}}))->decide(o), std::vector<int>{50});
  EXPECT_EQ(make_policy("learned_repartition", params({{"fixed_cost", "0.1"}}))->decide(o),
            std::vector<int>{50});  // 5.5
  EXPECT_EQ(make_policy("learned_repartition", params({{"fixed_cost", "0.08"}}))->decide(o),
            std::vector<int>{54});  // 4.4
  EXPECT_EQ(make_policy("learned_repartition", params({{"deadband", "0.05"}}))->decide(o), std::vector<int>{50});
  EXPECT_EQ(make_policy("learned_repartition", params({{"deadband", "0.04"}}))->decide(o), std::vector<int>{54});
}

// The trend extrapolates the corrected work's change: a block of work moving right by 2 slices per event is cut
// ahead of it with trend 1 and behind it (where it is now) with trend 0.
TEST(LearnedRepartition, TheTrendCutsAheadOfAMovingFront) {
  auto at = [](int start) {
    std::vector<double> w(100, 0.1);
    for (int s = start; s < start + 20; ++s) w[s] = 1.0;
    return w;
  };
  for (const char* trend : {"0", "1"}) {
    auto p = make_policy("learned_repartition", params({{"trend", trend}}));
    std::vector<int> b{50};
    for (int start = 20; start <= 30; start += 2) b = p->decide(observe(b, at(start), at(start)));
    const auto now = equal_share_targets(at(30), 2)[0];
    if (std::string(trend) == "0")
      EXPECT_NEAR(b[0], now, 0.5);
    else
      EXPECT_NEAR(b[0], equal_share_targets(at(32), 2)[0], 1.0);
  }
}

TEST(LearnedRepartition, ParametersAreCheckedAndTheBaseNeedsNoFile) {
  EXPECT_THROW(make_policy("learned_repartition", params({{"gain", "1.5"}})), InputError);
  EXPECT_THROW(make_policy("learned_repartition", params({{"trend", "-0.1"}})), InputError);
  EXPECT_THROW(make_policy("learned_repartition", params({{"gian", "0.1"}})), InputError);
  PolicyParams missing;
  missing.set("weights", "/no/such/file.h5");
  EXPECT_THROW(make_policy("learned_repartition", missing), InputError);
  EXPECT_TRUE(policy_needs("learned_repartition").slice_work);
  PolicyParams bad_cut;
  bad_cut.set("cut", "median");
  EXPECT_THROW(make_policy("persistence", bad_cut), InputError);
}

TEST(LearnedRepartition, WeightsRoundTripAndRefusals) {
  const auto dir = test::fresh_dir("learned_repartition_weights");
  const RepartitionParams p{0.25, 0.01, 0.5, 0.125, 0.0625, 0.03125};
  save_repartition_weights(dir + "/w.h5", p, {{"chosen", "global"}});
  const auto q = load_repartition_weights(dir + "/w.h5");
  for (const auto& d : repartition_params()) EXPECT_EQ(q.*d.field, p.*d.field) << d.name;
  EXPECT_FALSE(std::filesystem::exists(dir + "/w.h5.tmp"));
  auto refused = [&](const std::string& name, auto&& edit, const std::string& attr) {
    const auto path = dir + "/" + name + ".h5";
    std::filesystem::copy_file(dir + "/w.h5", path);
    {
      auto f = h5::File::open_write(path);
      edit(f);
    }
    try {
      load_repartition_weights(path);
      ADD_FAILURE() << name << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(attr), std::string::npos) << e.what();
    }
  };
  refused(
      "format",
      [](h5::File& f) {
        H5Adelete(f.id(), "format");
        f.write_attr("format", std::string("semlb-gru"));
      },
      "format");
  refused(
      "version",
      [](h5::File& f) {
        H5Adelete(f.id(), "version");
        f.write_attr("version", 2L);
      },
      "version");
  refused(
      "range",
      [](h5::File& f) {
        H5Adelete(f.id(), "gain");
        f.write_attr("gain", 1.5);
      },
      "gain");
  refused(
      "nan",
      [](h5::File& f) {
        H5Adelete(f.id(), "trend");
        f.write_attr("trend", std::nan(""));
      },
      "trend");
  refused(
      "missing", [](h5::File& f) { H5Adelete(f.id(), "move_cost"); }, "move_cost");
  PolicyParams by_file;
  by_file.set("weights", dir + "/w.h5");
  by_file.set("gain", "0");  // a parameter given overrides the file's
  EXPECT_NO_THROW(make_policy("learned_repartition", by_file));
}

TEST(LearnedRepartition, StateRefusesAnotherShape) {
  auto p = make_policy("learned_repartition", params({{"gain", "0.3"}}));
  EXPECT_THROW(p->load_state({{"correction", {1.0, 1.0}}, {"previous", {1.0}}}), InputError);
  EXPECT_THROW(p->load_state({{"correction", {1.0, 50.0}}, {"previous", {}}}), InputError);
  EXPECT_THROW(p->load_state({{"hidden", {1.0}}}), InputError);
  EXPECT_NO_THROW(p->load_state({{"correction", {1.0, 2.0}}, {"previous", {}}}));
}
