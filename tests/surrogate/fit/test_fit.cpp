// semlb fit: its config's refusals, its objective against the replay and the surrogate run directly, and a small fit.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "../../run_command.hpp"
#include "common/errors.hpp"
#include "controllers/learned_repartition.hpp"
#include "controllers/policy.hpp"
#include "controllers/workload.hpp"
#include "surrogate/fit/fit.hpp"
#include "surrogate/rollout.hpp"
#include "surrogate/scenario.hpp"
#include "surrogate/workload_replay.hpp"

using namespace semlb;
using semlb::test::fresh_dir;
using semlb::test::source;

namespace {

const std::string kSmall = source("results/cpu/workloads/small_dev_s1.h5");

std::string write(const std::string& dir, const std::string& text) {
  const auto path = dir + "/fit.yaml";
  std::ofstream(path) << text;
  return path;
}

void refused(const std::string& text, const std::string& what) {
  const auto dir = fresh_dir("fit_refusal");
  try {
    fit::load_fit_config(write(dir, text), {});
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Fit, ConfigRefusalsNameTheFileLineAndField) {
  refused("workloads: " + kSmall + "\nevaluatons: 3\n", "fit.yaml:2: field 'evaluatons': unknown fit setting");
  refused("workloads: /no/such.h5\n", "field 'workloads': no such workload file '/no/such.h5'");
  refused("workloads: " + kSmall + "\nfree: gain,speed\n",
          "field 'free': 'speed' is not a learned_repartition parameter");
  refused("workloads: " + kSmall + "\nvalidation_surrogate_seeds: 9000\n",
          "must lie in the validation range 8000-8999");
  refused("workloads: " + kSmall + "\nregret_weight: -1\n", "field 'regret_weight'");
  refused("workloads: " + kSmall + "\nranks: 2,one\n", "ranks");
  refused("surrogate_episodes: 0\n", "nothing to fit on");
  refused("workloads: " + kSmall + "\nfree: \"\"\n", "field 'free': must name at least one parameter");
  refused("workloads: " + kSmall + "\nfree: gain,gain\n", "field 'free': 'gain' is named twice");
  refused("workloads: " + source("results") + "\n", "is not a file");
  EXPECT_THROW(fit::load_fit_config("", {"evaluations"}), InputError);  // not KEY=VALUE
}

// The fit's objective is the replay's and the surrogate's own numbers: each episode's loop through replay_workload
// and rollout with the registered policy, over the lower of the base rule's and static's.
TEST(Fit, ObjectiveIsTheReplaysAndTheSurrogatesLoopOverTheReference) {
  const auto dir = fresh_dir("fit_parity");
  const auto c = fit::load_fit_config(write(dir, "workloads: " + kSmall +
                                                     "\nranks: 2,4\nreplay_seeds: 3\n"
                                                     "surrogate_episodes: 2\nsurrogate_events: 30\nregret_weight: 0\n"
                                                     "surrogate_weight: 0.5\nthreads: 2\n"),
                                      {});
  const fit::EpisodeSet set(c, false);
  ASSERT_EQ(set.size(), 4u);
  PolicyParams chosen, base;
  chosen.set("weights", "none"), chosen.set("gain", "0.3"), chosen.set("fixed_cost", "0.02");
  base.set("weights", "none");
  const RepartitionParams p{0.3, 0, 0, 0, 0, 0.02};
  auto loop = [&](int i, PolicyParams params, const std::string& name) {
    auto policy = make_policy(name, params);
    if (i < 2) {
      surrogate::WorkloadReplay r;
      r.ranks = i == 0 ? 2 : 4;
      r.seed = 3;
      return surrogate::replay_workload(read_workload(kSmall), r, *policy, name, kSmall).loop_s;
    }
    const auto s = surrogate::make_scenario(i - 2, i == 2 ? 2 : 4);
    const auto res = surrogate::rollout(s, *policy, 30);
    return res.events * (1 + res.mean_max_over_mean) + static_cast<double>(res.migration) * s.ranks / s.slices;
  };
  double w = 0, s = 0;
  for (int i = 0; i < 4; ++i) {
    const double ref = std::min(loop(i, base, "learned_repartition"), loop(i, PolicyParams{}, "static"));
    (i < 2 ? w : s) += loop(i, chosen, "learned_repartition") / ref / 2;
  }
  EXPECT_DOUBLE_EQ(set.objective(p), 0.5 * w + 0.5 * s);
  EXPECT_NE(set.objective(p), set.objective(RepartitionParams{}));
}

// A small fit: the file it writes loads, holds the candidate with the lowest validation objective, and does not
// depend on the thread count; its log has one row per evaluation.
TEST(Fit, ASmallFitWritesTheCandidateValidationChose) {
  const auto dir = fresh_dir("fit_small");
  const std::string text = "workloads: " + kSmall +
                           "\nvalidation: " + source("results/cpu/workloads/small_epidermis_s1.h5") +
                           "\nranks: 2,4\nreplay_seeds: 100\nsurrogate_episodes: 2\nsurrogate_events: 30\n"
                           "validation_surrogate_seeds: 8000-8001\nevaluations: 12\npolish: 6\n";
  std::vector<fit::FitResult> res;
  for (const char* threads : {"1", "2"}) {
    const auto c = fit::load_fit_config(write(dir, text), {std::string("threads=") + threads});
    fit::FitOptions o;
    o.out = dir + "/w" + threads + ".h5";
    o.progress = false;
    res.push_back(fit::run_fit(c, o));
  }
  const auto& r = res[0];
  ASSERT_EQ(r.candidates.size(), res[1].candidates.size());
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    EXPECT_EQ(r.candidates[i].train, res[1].candidates[i].train) << i;
    EXPECT_EQ(r.candidates[i].validation, res[1].candidates[i].validation) << i;
    EXPECT_GE(r.candidates[i].validation, r.candidates[r.chosen].validation) << i;
  }
  EXPECT_EQ(r.candidates[0].name, "base");
  EXPECT_GT(r.candidates.size(), 3u + 48u);  // base, global, polished, the shortlist and the grid
  const auto w = load_repartition_weights(dir + "/w1.h5");
  for (const auto& d : repartition_params()) EXPECT_EQ(w.*d.field, r.candidates[r.chosen].params.*d.field) << d.name;
  std::ifstream log(dir + "/w1.log.csv");
  long lines = 0;
  for (std::string line; std::getline(log, line);) ++lines;
  EXPECT_EQ(lines, r.evaluations + 1);
  EXPECT_FALSE(std::filesystem::exists(dir + "/w1.h5.tmp"));
}

TEST(Fit, CommandLineErrorsExitTwo) {
  const auto dir = fresh_dir("fit_cli");
  auto r = test::run(test::semlb_bin() + " fit --config " + write(dir, "workloads: /no/such.h5\n") + " --out " + dir +
                     "/w.h5");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("field 'workloads'"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/w.h5"));
  // an --out that is a folder is refused before the search, and nothing is written beside it
  const auto config = write(dir, "workloads: " + kSmall + "\nranks: 2\nsurrogate_episodes: 1\nevaluations: 2\n");
  std::filesystem::create_directory(dir + "/folder");
  r = test::run(test::semlb_bin() + " fit --config " + config + " --out " + dir + "/folder --quiet");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("--out: '" + dir + "/folder' is a folder"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/folder.log.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/folder.tmp"));
  r = test::run(test::semlb_bin() + " fit --out " + dir + "/w.h5");  // the config is required
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("--config"), std::string::npos) << r.out;
  r = test::run(test::semlb_bin() + " fit --help");
  EXPECT_EQ(r.rc, 0);
  EXPECT_NE(r.out.find("--config"), std::string::npos) << r.out;
}
