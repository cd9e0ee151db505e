// The replay_score runner: every trace.jsonl under its folder, one row per (trace, policy), equal to `semlb replay
// --score`; bad traces and folders refused before any output.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "../run_command.hpp"
#include "common/text_io.hpp"

using namespace semlb::test;
namespace fs = std::filesystem;

namespace {

// S = 4, P = 2, min width 1, from boundary 2. static keeps it: times (2,2), (4,2): I = 0, 2/3 -> mean 1/3.
const char* kTraceA =
    "{\"event\":0,\"slices\":4,\"min_width\":1,\"boundaries\":[2],\"times\":[2,2],\"slice_work\":[1,1,1,1]}\n"
    "{\"event\":1,\"slices\":4,\"min_width\":1,\"boundaries\":[2],\"times\":[4,2],\"slice_work\":[3,1,1,1]}\n";
// S = 6, P = 3, from [2, 4]; static: times (2,2,2), (2,2,5), (2,2,5): I = 0, 1, 1 -> mean 2/3.
const char* kTraceB =
    "{\"event\":0,\"slices\":6,\"min_width\":1,\"boundaries\":[2,4],\"times\":[2,2,2],\"slice_work\":[1,1,1,1,1,1]}\n"
    "{\"event\":1,\"slices\":6,\"min_width\":1,\"boundaries\":[2,4],\"times\":[2,2,5],\"slice_work\":[1,1,1,1,1,4]}\n"
    "{\"event\":2,\"slices\":6,\"min_width\":1,\"boundaries\":[2,4],\"times\":[2,2,5],\"slice_work\":[1,1,1,1,1,4]}\n";

std::string manifest(const std::string& traces) {
  return "name: rs\nrunner: replay_score\noutput: rs/rs.csv\naxes:\n  policy: [static, reactive, lammps_shift]\nset:\n"
         "  traces: " +
         traces + "\n";
}

}  // namespace

TEST(ReplayScore, OneRowPerTraceAndPolicyEqualToReplayScore) {
  const auto dir = fresh_dir("replay_score_runner");
  fs::create_directories(dir + "/res/load_balance/runs/policy=static");
  fs::create_directories(dir + "/res/gpu/rank_balance/runs/policy=gru");
  write(dir + "/res/load_balance/runs/policy=static/trace.jsonl", kTraceA);
  write(dir + "/res/gpu/rank_balance/runs/policy=gru/trace.jsonl", kTraceB);
  write(dir + "/res/gpu/rank_balance/runs/policy=gru/other.jsonl", "not a trace\n");  // only trace.jsonl is read
  write(dir + "/m.yaml", manifest("res"));  // relative to the manifest's folder
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  auto lines = semlb::split(slurp(dir + "/out/rs/rs.csv"), '\n');
  ASSERT_EQ(lines.size(), 1u + 6u + 1u) << slurp(dir + "/out/rs/rs.csv");  // header, 3 policies x 2 traces, ""
  EXPECT_EQ(lines[0], "policy,trace,ranks,slices,events,mean_imbalance,migration,mean_max_over_mean");
  int checked = 0;
  for (size_t i = 1; i + 1 < lines.size(); ++i) {
    const auto f = semlb::split(lines[i], ',');
    ASSERT_EQ(f.size(), 8u) << lines[i];
    const auto replay =
        run(semlb_bin() + " replay --score --policy " + f[0] + " --trace " + dir + "/res/" + f[1] + "/trace.jsonl");
    ASSERT_EQ(replay.rc, 0) << replay.out;
    const auto want = nlohmann::json::parse(replay.out);
    EXPECT_EQ(std::stol(f[4]), want["events"].get<long>()) << lines[i];
    EXPECT_DOUBLE_EQ(std::stod(f[5]), want["mean_imbalance"].get<double>()) << lines[i];
    EXPECT_EQ(std::stol(f[6]), want["migration"].get<long>()) << lines[i];
    EXPECT_DOUBLE_EQ(std::stod(f[7]), want["mean_max_over_mean"].get<double>()) << lines[i];
    ++checked;
  }
  EXPECT_EQ(checked, 6);
  // The hand-computed static rows, sorted by path: gpu/... before load_balance/...
  EXPECT_NE(lines[1].find("static,gpu/rank_balance/runs/policy=gru,3,6,3,"), std::string::npos) << lines[1];
  EXPECT_NEAR(std::stod(semlb::split(lines[1], ',')[5]), 2.0 / 3.0, 1e-12);
  EXPECT_NE(lines[2].find("static,load_balance/runs/policy=static,2,4,2,"), std::string::npos) << lines[2];
  EXPECT_NEAR(std::stod(semlb::split(lines[2], ',')[5]), 1.0 / 3.0, 1e-12);
  EXPECT_EQ(semlb::split(lines[2], ',')[6], "0");
}

TEST(ReplayScore, BadTracesAndFoldersAreRefusedBeforeAnyOutput) {
  const auto dir = fresh_dir("replay_score_bad");
  fs::create_directories(dir + "/res/a/runs/x");
  fs::create_directories(dir + "/res/b/runs/y");
  write(dir + "/res/a/runs/x/trace.jsonl", kTraceA);
  // The second line lacks slice_work: --score refuses it, naming the file, line and field.
  write(dir + "/res/b/runs/y/trace.jsonl",
        "{\"event\":0,\"slices\":4,\"min_width\":1,\"boundaries\":[2],\"times\":[2,2],\"slice_work\":[1,1,1,1]}\n"
        "{\"event\":1,\"slices\":4,\"min_width\":1,\"boundaries\":[2],\"times\":[4,2]}\n");
  write(dir + "/m.yaml", manifest("res"));
  auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("res/b/runs/y/trace.jsonl:2: field 'slice_work': missing"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out/rs/rs.csv"));
  EXPECT_FALSE(fs::exists(dir + "/out/rs/rs.csv.partial"));

  write(dir + "/m.yaml", manifest("nowhere"));
  r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("m.yaml:7: field 'traces': "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("is not a folder"), std::string::npos) << r.out;

  fs::create_directories(dir + "/empty");
  write(dir + "/m.yaml", manifest("empty"));
  r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("no trace.jsonl under"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out/rs/rs.csv"));
}
