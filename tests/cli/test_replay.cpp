// `semlb replay --score` on a hand-computed trace, and replay's input errors (FILE:LINE: field, exit 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>
#include <nlohmann/json.hpp>

#include "../run_command.hpp"
#include "../workload_fixtures.hpp"

using namespace semlb::test;

namespace {

void expect_bad_input(const std::string& args, const std::string& message) {
  const auto r = run(semlb_bin() + " " + args);
  EXPECT_EQ(r.rc, 2) << args << "\n" << r.out;
  EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

// S = 4, P = 2, min width 1, starting at boundary 2; the recorded boundaries after the first line and the
// recorded times are not used by --score (the policy's own partition and the slice work decide).
const char* kTrace =
    "{\"event\":0,\"slices\":4,\"min_width\":1,\"boundaries\":[2],\"times\":[9,9],\"slice_work\":[1,1,1,1]}\n"
    "{\"event\":1,\"slices\":4,\"min_width\":1,\"boundaries\":[3],\"times\":[9,9],\"slice_work\":[3,1,1,1]}\n"
    "{\"event\":2,\"slices\":4,\"min_width\":1,\"boundaries\":[1],\"times\":[9,9],\"slice_work\":[1,1,1,3]}\n";

nlohmann::json score(const std::string& trace, const std::string& policy_args) {
  const auto r = run(semlb_bin() + " replay --score --trace " + trace + " " + policy_args);
  EXPECT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST(Replay, ScoreOfAHandComputedTrace) {
  const auto dir = fresh_dir("replay_score");
  write(dir + "/t.jsonl", kTrace);
  // static keeps 2: times (2,2), (4,2), (2,4): I = 0, 2/3, 2/3; (T_max - T_mean)/T_mean = 0, 1/3, 1/3.
  auto s = score(dir + "/t.jsonl", "--policy static");
  EXPECT_EQ(s["events"], 3);
  EXPECT_EQ(s["migration"], 0);
  EXPECT_NEAR(s["mean_imbalance"].get<double>(), 4.0 / 9.0, 1e-15);
  EXPECT_NEAR(s["mean_max_over_mean"].get<double>(), 2.0 / 9.0, 1e-15);
  // reactive alpha 1.5: event 0 balanced, no move; event 1 (4,2): |ds| = 1.5*2*2/(2*4) = 0.75 -> 1 toward the
  // slower left rank: b = 1; event 2 under b = 1: (1,5), I = 4/3, excess 2/3; |ds| = 1.5*3*4/(2*5) = 1.8 -> 2: b = 3.
  s = score(dir + "/t.jsonl", "--policy reactive --param reactive.alpha=1.5");
  EXPECT_EQ(s["migration"], 3);
  EXPECT_NEAR(s["mean_imbalance"].get<double>(), 2.0 / 3.0, 1e-15);
  EXPECT_NEAR(s["mean_max_over_mean"].get<double>(), 1.0 / 3.0, 1e-15);
  // foresight without a move cost balances intervals 1 and 2 (b = 1, then 3): 3 slices, no imbalance.
  s = score(dir + "/t.jsonl", "--policy foresight --param foresight.lambda=0");
  EXPECT_EQ(s["migration"], 3);
  EXPECT_EQ(s["mean_imbalance"].get<double>(), 0.0);
}

TEST(Replay, ErrorsNameFileLineAndField) {
  const auto dir = fresh_dir("replay_errors");
  const std::string ok = "\"slices\":4,\"min_width\":1,\"boundaries\":[2],\"times\":[1,1]";
  write(dir + "/unknown.jsonl", "{\"event\":0," + ok + "}\n{\"event\":1," + ok + ",\"tiems\":[1,1]}\n");
  expect_bad_input("replay --policy static --trace " + dir + "/unknown.jsonl",
                   "unknown.jsonl:2: field 'tiems': unknown key");
  write(dir + "/twice.jsonl", "{\"event\":0,\"event\":1," + ok + "}\n");
  expect_bad_input("replay --policy static --trace " + dir + "/twice.jsonl",
                   "twice.jsonl:1: field 'event': given twice");
  write(dir + "/times.jsonl", "\n{\"event\":0,\"slices\":4,\"min_width\":1,\"boundaries\":[2],\"times\":[1,-1]}\n");
  expect_bad_input("replay --policy static --trace " + dir + "/times.jsonl",
                   "times.jsonl:2: field 'times': event 0: times[1]");
  write(dir + "/nowork.jsonl", std::string(kTrace) + "{\"event\":3," + ok + "}\n");
  expect_bad_input("replay --score --policy static --trace " + dir + "/nowork.jsonl",
                   "nowork.jsonl:4: field 'slice_work': missing");
  expect_bad_input("replay --policy persistence --trace " + dir + "/unknown.jsonl",
                   "unknown.jsonl:2: field 'tiems'");  // the whole trace is read before any decision
  write(dir + "/nowork1.jsonl", "{\"event\":0," + ok + "}\n");
  expect_bad_input("replay --policy persistence --trace " + dir + "/nowork1.jsonl",
                   "nowork1.jsonl:1: policy 'persistence': event 0: policy 'persistence' needs slice_work");
  expect_bad_input("replay --policy foresight --trace " + dir + "/nowork1.jsonl",
                   "nowork1.jsonl:1: policy 'foresight'");
  // a parameter's error names its --param, as `semlb surrogate`'s do; a parameter of another policy is refused
  for (const auto& [param, message] : std::vector<std::pair<std::string, std::string>>{
           {"holt.alpha=2", "--param holt.alpha: policy parameter 'alpha': '2' is outside (0, 1]"},
           {"holt.alpah=0.2", "--param holt.alpah: policy 'holt' has no parameter 'alpah'"},
           {"reactive.tau=0.1", "--param reactive.tau: the replayed policy is 'holt'"}})
    expect_bad_input("replay --policy holt --trace " + dir + "/nowork1.jsonl --param " + param, message);
}

// `semlb replay --workload F --ranks P`: the time model on the hand workload (tests/workload_fixtures.hpp)
// through the CLI, and its refusals (exit 2, one line).
TEST(Replay, WorkloadAtARankCountThroughTheTimeModel) {
  const auto dir = fresh_dir("replay_workload");
  semlb::write_workload(dir + "/w.h5", semlb::test::hand_workload());
  const std::string exact =
      " --time-model ghost_weight=0.5 --time-model speed_spread=0 --time-model jitter=0"
      " --time-model seconds_per_work=0.5 --time-model migrate_s_per_slice=0";
  const auto r = run(semlb_bin() + " replay --policy static --workload " + dir + "/w.h5 --ranks 2" + exact);
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out.substr(0, r.out.find('\n')));  // the JSON line (stdout), then the table
  EXPECT_DOUBLE_EQ(j["mean_imbalance"].get<double>(), 2.0 / 4.5);
  // The terminal's table (stderr): one row per policy and P, the imbalance in %.
  EXPECT_NE(r.out.find("\npolicy | P | events | imbalance % | migration | loop s | ideal s | migrate s\n"
                       "static | 2 | 2      | 44.44       | 0         | 11     | "),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.back(), '\n');
  EXPECT_DOUBLE_EQ(j["loop_s"].get<double>(), 11.0);
  EXPECT_EQ(j["ranks"], 2);
  EXPECT_EQ(j["events"], 2);
  expect_bad_input("replay --policy static --workload " + dir + "/w.h5", "--workload needs --ranks P");
  expect_bad_input("replay --policy static --workload " + dir + "/w.h5 --ranks 5",
                   "5 ranks of at least 1 slices do not fit in 4 slices");
  expect_bad_input("replay --policy static --workload " + dir + "/w.h5 --ranks 2 --time-model jitter=lots",
                   "--time-model jitter: 'lots' is not a number");
  expect_bad_input("replay --policy static --workload " + dir + "/w.h5 --ranks 2 --time-model speed=1",
                   "--time-model speed: unknown time model key (known: ");
  expect_bad_input(
      "replay --policy static --workload " + dir + "/w.h5 --ranks 2 --time-model truth=work --time-model truth=auto",
      "--time-model truth: given twice");
  // the list keys act on a version 3 file's list seconds only: refused where they would do nothing
  expect_bad_input(
      "replay --policy static --workload " + dir + "/w.h5 --ranks 2 --time-model list_by=work",
      dir + "/w.h5: time model list_by: the file has no list seconds (part_seconds: a version 3 workload)");
  const std::string v3 = source("results/gpu/measured/runs/epidermis_development/record/workload.h5");
  expect_bad_input(
      "replay --policy static --workload " + v3 + " --ranks 2 --time-model truth=work --time-model element_s=1e-9",
      v3 + ": time model element_s: truth=work replays W_s, which has no list seconds");
  expect_bad_input("replay --policy static --workload " + v3 + " --ranks 2 --time-model element_s=2",
                   "--time-model element_s: '2' is outside [0, 1]");
  const auto ok =
      run(semlb_bin() + " replay --policy static --workload " + v3 + " --ranks 2 --time-model list_by=work");
  EXPECT_EQ(ok.rc, 0) << ok.out;
  expect_bad_input("replay --policy static --workload " + dir + "/t.jsonl --ranks 2", "t.jsonl");
  expect_bad_input("replay --policy static", "give --trace or --workload");
  expect_bad_input("replay --policy static --workload " + dir + "/w.h5 --ranks 2 --score", "--score is for --trace");
  write(dir + "/t.jsonl", "");
  for (const char* flag :
       {"--ranks 2", "--seed 1", "--coarsen 2", "--events 3", "--first-event 1", "--time-model jitter=0"})
    expect_bad_input("replay --policy static --trace " + dir + "/t.jsonl " + flag,
                     std::string(flag).substr(0, std::string(flag).find(' ')) + " is for --workload, not --trace");
}
