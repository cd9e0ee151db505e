// The mpi_sim / mpi_intervals / mpi_end_to_end runners: POLICY.KEY parameters, load-time refusals, typed values,
// rank_times.csv, launches, checkpoint/restart segments.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>

#include "../run_command.hpp"
#include "common/text_io.hpp"
#include "engine/io/io.hpp"
#include "engine/run/driver.hpp"

using namespace semlb::test;
namespace fs = std::filesystem;

namespace {
// Two rows of 60 cells on 2 ranks, 20 steps: seconds each.
std::string engine_manifest(const std::string& axes, const std::string& set) {
  return "name: engine\nrunner: mpi_sim\noutput: engine.csv\naxes:\n" + axes +
         "set:\n  scene: " + source("scenes/epidermis.yaml") +
         "\n  ranks: 2\n  cells: 60\n  steps: 20\n  rebalance_every: 10\n" + set;
}
}  // namespace

// holt.alpha / holt.beta reach holt's rows as decomposition.params (the engine builds holt with them) and are
// left out of static's rows (which would refuse them as unknown parameters), as in the surrogate runner.
TEST(MpiRunners, PolicyParametersReachTheRowsOfTheirPolicyOnly) {
  const auto dir = fresh_dir("mpi_policy_params");
  write(dir + "/m.yaml", engine_manifest("  policy: [static, holt]\n", "  holt.alpha: 0.3\n  holt.beta: 0.1\n"));
  const auto r =
      run(semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --keep-runs --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  std::map<std::string, YAML::Node> scene;  // each row's scene as run, by policy
  for (const auto& e : fs::directory_iterator(dir + "/out/runs")) {
    const auto node = YAML::LoadFile((e.path() / "scene.yaml").string());
    scene[node["decomposition"]["policy"].as<std::string>()] = node;
  }
  ASSERT_EQ(scene.size(), 2u);
  const auto holt = scene.at("holt")["decomposition"]["params"];
  ASSERT_TRUE(holt.IsMap()) << r.out;
  EXPECT_EQ(holt["alpha"].as<std::string>(), "0.3");
  EXPECT_EQ(holt["beta"].as<std::string>(), "0.1");
  EXPECT_EQ(holt.size(), 2u);
  EXPECT_FALSE(scene.at("static")["decomposition"]["params"]);
}

// A bad policy parameter, also of a policy the row does not run, stops the sweep before anything runs.
TEST(MpiRunners, BadPolicyParameterIsRefusedAtItsLine) {
  const auto dir = fresh_dir("mpi_bad_param");
  write(dir + "/m.yaml", engine_manifest("  policy: [static, reactive]\n", "  holt.alpha: 7\n"));
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("m.yaml:12: field 'holt.*': policy parameter 'alpha': '7' is outside (0, 1]"), std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

// A policy that needs the true work of the next interval (PolicyNeeds::true_work) cannot be fed by a
// simulation: the sweep refuses the manifest before its first row runs, naming where the policy was set.
TEST(MpiRunners, OraclePoliciesAreRefusedBeforeAnythingRuns) {
  const auto dir = fresh_dir("mpi_oracle");
  auto refused = [&](const std::string& manifest_text, const std::string& sets, const std::string& want) {
    write(dir + "/m.yaml", manifest_text);
    fs::remove_all(dir + "/out");
    const auto r = run(within(60) + semlb_bin() + " sweep " + dir + "/m.yaml --quiet --keep-runs --results " + dir +
                       "/out" + sets);
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_NE(r.out.find(want), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_FALSE(fs::exists(dir + "/out")) << "the static row ran: " << r.out;
  };
  refused(engine_manifest("  policy: [static, oracle]\n", ""), "",
          "m.yaml:5: field 'policy': 'oracle' needs the true work of the next interval");
  refused(engine_manifest("  policy: [static]\n", ""), " --set policy=static,lazy_oracle",
          "--set policy: 'lazy_oracle' needs the true work");
  refused(engine_manifest("  initial: [workload]\n", "  scene.decomposition.policy: oracle\n"), "",
          "m.yaml:12: field 'scene.decomposition.policy': 'oracle' needs the true work");
  // the policy of the scene file itself
  write(dir + "/oracle.yaml", slurp(source("scenes/epidermis.yaml")) + "decomposition:\n  policy: lazy_oracle\n");
  std::string text = engine_manifest("  initial: [workload]\n", "");
  text.replace(text.find(source("scenes/epidermis.yaml")), source("scenes/epidermis.yaml").size(), "oracle.yaml");
  refused(text, "", "oracle.yaml:38: field 'decomposition.policy': 'lazy_oracle' needs the true work");
  // an unknown policy too, where before it failed inside mpirun after the earlier rows had run
  refused(engine_manifest("  policy: [static, holtt]\n", ""), "", "m.yaml:5: field 'policy': unknown policy 'holtt'");
}

// A named scene setting is type-checked at its manifest line, before anything runs.
TEST(MpiRunners, SceneSettingsAreTypedAtTheirLine) {
  const auto dir = fresh_dir("mpi_typed");
  write(dir + "/m.yaml", engine_manifest("  policy: [static]\n", "  initial: uniform\n"));
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out --set cells=60.5");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("--set cells: '60.5' is not an integer"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
  std::string text = engine_manifest("  policy: [static]\n", "");
  text.replace(text.find("rebalance_every: 10"), 19, "rebalance_every: often");
  write(dir + "/m.yaml", text);
  const auto again = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  EXPECT_EQ(again.rc, 2) << again.out;
  EXPECT_NE(again.out.find("m.yaml:11: field 'rebalance_every': 'often' is not an integer"), std::string::npos)
      << again.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

// An effect's bad parameter (here a scene.* setting of the manifest) is refused by --check and before anything is
// launched, exit 2 naming the setting, as engine_timing does: not by a launch that fails mid-sweep.
TEST(MpiRunners, EffectParametersAreCheckedBeforeAnythingIsLaunched) {
  const auto dir = fresh_dir("mpi_effects");
  write(dir + "/m.yaml", engine_manifest("  policy: [static]\n", "  scene.effects.growth.cycle_time: -1\n"));
  for (const std::string flag : {" --check", ""}) {
    const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out" + flag);
    EXPECT_EQ(r.rc, 2) << flag << ": " << r.out;
    EXPECT_NE(r.out.find("effects.growth.cycle_time"), std::string::npos) << flag << ": " << r.out;
    EXPECT_FALSE(fs::exists(dir + "/out")) << flag;
  }
}

// rank_times.csv is written in engine::rank_times::kColumns' order, and mpi_intervals copies its columns by name.
TEST(MpiRunners, RankTimesColumnsAreTheDeclaredOnes) {
  const auto dir = fresh_dir("mpi_intervals");
  std::string text = engine_manifest("  policy: [reactive]\n", "  scene.decomposition.timing: modelled\n");
  text.replace(text.find("mpi_sim"), 7, "mpi_intervals");
  write(dir + "/m.yaml", text);
  const auto r =
      run(semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --keep-runs --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  std::string header;
  for (const char* c : semlb::engine::rank_times::kColumns) (header += header.empty() ? "" : ",") += c;
  std::vector<fs::path> kept;
  for (const auto& e : fs::directory_iterator(dir + "/out/runs")) kept.push_back(e.path());
  ASSERT_EQ(kept.size(), 1u);
  const auto times = semlb::split(slurp((kept[0] / semlb::engine::rank_times::kFile).string()), '\n');
  ASSERT_EQ(times.size(), 1u + 2u * 2u + 1u) << "header, 2 events x 2 ranks, the empty field after the last newline";
  EXPECT_EQ(times[0], header);
  const auto csv = semlb::split(slurp(dir + "/out/engine.csv"), '\n');
  EXPECT_EQ(csv.at(0), "policy,step,rank,compute_s,imbalance,moved_slices");
  ASSERT_EQ(csv.size(), times.size());
  for (size_t i = 1; i + 1 < times.size();
       ++i) {  // same step, rank, imbalance, moved slices; compute_s 0 under --no-timing
    const auto f = semlb::split(times[i], ','), g = semlb::split(csv[i], ',');
    EXPECT_EQ(g, (std::vector<std::string>{"reactive", f[0], f[1], "0", f[5], f[6]})) << csv[i];
  }
}

// mpi_end_to_end with `launches: 2`: the paper's load-balance columns, one row per launch, launch-major (launch 1
// of every policy and initial partition, then launch 2), in the order the launches ran; the modelled timing
// makes each launch's decisions, and so its imbalance and migration, the same.
TEST(MpiRunners, EndToEndRowsPerLaunchInterleaved) {
  const auto dir = fresh_dir("mpi_end_to_end");
  std::string text =
      "name: e2e\nrunner: mpi_end_to_end\noutput: e2e/load_balance.csv\nlaunches: 2\ngroups:\n"
      "  - {policy: [static, reactive], initial: [workload]}\n  - {policy: [static], initial: [uniform]}\n"
      "set:\n  scene: " +
      source("scenes/epidermis.yaml") +
      "\n  ranks: 2\n  cells: 60\n  steps: 20\n  rebalance_every: 10\n  gpus: 0\n  bind_to: none\n"
      "  scene.decomposition.timing: modelled\n";
  write(dir + "/m.yaml", text);
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --quiet --keep-runs --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto lines = semlb::split(slurp(dir + "/out/e2e/load_balance.csv"), '\n');
  ASSERT_EQ(lines.size(), 1u + 6u + 1u) << "header, 3 rows x 2 launches, the empty field after the last newline";
  EXPECT_EQ(lines[0],
            "policy,initial,launch,gpus,ranks,cells_start,cells_end,steps,loop_s,compute_s,mean_imbalance,"
            "migrated_slices,machine");
  const std::vector<std::vector<std::string>> keys = {{"static", "workload", "1"},   {"reactive", "workload", "1"},
                                                      {"static", "uniform", "1"},    {"static", "workload", "2"},
                                                      {"reactive", "workload", "2"}, {"static", "uniform", "2"}};
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 1; i <= 6; ++i) rows.push_back(semlb::split(lines[i], ','));
  for (size_t i = 0; i < 6; ++i) {
    ASSERT_EQ(rows[i].size(), 13u) << lines[i + 1];
    EXPECT_EQ((std::vector<std::string>{rows[i][0], rows[i][1], rows[i][2]}), keys[i]) << lines[i + 1];
    EXPECT_EQ(rows[i][3], "0");
    EXPECT_EQ(rows[i][4], "2");
    EXPECT_EQ(rows[i][5], "60");
    EXPECT_EQ(rows[i][7], "20");
    EXPECT_GT(std::stod(rows[i][8]), 0.0) << "loop_s is measured";
    EXPECT_GT(std::stod(rows[i][9]), 0.0) << "compute_s is measured";
    EXPECT_NE(rows[i][12].find("default placement"), std::string::npos) << rows[i][12];
  }
  for (size_t i = 0; i < 3; ++i)  // the same decisions in both launches: cells, imbalance and migration agree
    for (size_t c : {6u, 10u, 11u}) EXPECT_EQ(rows[i][c], rows[i + 3][c]) << i << " column " << c;
  // the launches ran in that order: each kept run's files are newer than the previous row's
  std::vector<fs::file_time_type> ran;
  for (size_t i = 0; i < 6; ++i) {
    std::string label;
    for (const auto& e : fs::directory_iterator(dir + "/out/e2e/runs"))
      if (e.path().filename().string().find("launch=" + keys[i][2] + "_") == 0 &&
          e.path().filename().string().find("policy=" + keys[i][0]) != std::string::npos &&
          e.path().filename().string().find("initial=" + keys[i][1]) != std::string::npos)
        label = e.path().string();
    ASSERT_FALSE(label.empty()) << i;
    ran.push_back(fs::last_write_time(label + "/run.csv"));
  }
  for (size_t i = 1; i < 6; ++i) EXPECT_LT(ran[i - 1], ran[i]) << i;
  // placement words are checked before anything runs
  write(dir + "/bad.yaml", text + "  map_by: \"core;rm\"\n");
  const auto bad = run(semlb_bin() + " sweep " + dir + "/bad.yaml --quiet --results " + dir + "/bad");
  EXPECT_EQ(bad.rc, 2) << bad.out;
  EXPECT_NE(bad.out.find("bad.yaml:17: field 'map_by': must be an mpirun placement word"), std::string::npos)
      << bad.out;
}

// mpi_end_to_end with `segments: 2`: each launch runs as two `semlb sim` invocations, the second resuming from the
// first's checkpoint. With modelled rank times the decisions are reproducible, so the split launch gives the unsplit
// one's row (cells, imbalance, migrated slices), trace.jsonl line for line, rank_times.csv's modelled columns and the
// final state bit for bit; reactive (a tiny threshold, so that it moves slices) and gru (a hidden state to carry),
// split between two events (step 15 of 30, an event every 10 steps).
TEST(MpiRunners, EndToEndSegmentsContinueTheUnsplitLaunch) {
  const auto dir = fresh_dir("mpi_end_to_end_segments");
  const std::string text =
      "name: e2e\nrunner: mpi_end_to_end\noutput: e2e/load_balance.csv\naxes:\n"
      "  policy: [reactive, gru]\n  segments: [1, 2]\nset:\n  scene: " +
      source("scenes/epidermis.yaml") +
      "\n  ranks: 2\n  cells: 60\n  steps: 30\n  rebalance_every: 10\n  reactive.tau: 0.001\n"
      "  scene.decomposition.timing: modelled\n";
  write(dir + "/m.yaml", text);
  const auto r = run(within(300) + semlb_bin() + " sweep " + dir +
                     "/m.yaml --no-timing --quiet --keep-runs --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto lines = semlb::split(slurp(dir + "/out/e2e/load_balance.csv"), '\n');
  ASSERT_EQ(lines.size(), 1u + 4u + 1u)
      << "header, 2 policies x 2 segment counts, the empty field after the last newline";
  EXPECT_EQ(lines[0],
            "segments,policy,initial,launch,gpus,ranks,cells_start,cells_end,steps,loop_s,compute_s,"
            "mean_imbalance,migrated_slices,machine");
  auto run_dir = [&](const std::string& policy, int segments) {
    for (const auto& e : fs::directory_iterator(dir + "/out/e2e/runs"))
      if (e.path().filename().string().find("policy=" + policy + "_segments=" + std::to_string(segments)) !=
          std::string::npos)
        return e.path().string();
    return std::string();
  };
  auto modelled_columns = [](const std::string& file) {  // rank_times.csv less the measured exchange/migration seconds
    std::vector<std::string> out;
    for (const auto& line : semlb::split(slurp(file), '\n')) {
      const auto f = semlb::split(line, ',');
      if (f.size() == 7) out.push_back(f[0] + "," + f[1] + "," + f[2] + "," + f[5] + "," + f[6]);
    }
    return out;
  };
  for (size_t p = 0; p < 2; ++p) {
    const auto whole = semlb::split(lines[1 + 2 * p], ','), split = semlb::split(lines[2 + 2 * p], ',');
    ASSERT_EQ(whole.size(), 14u) << lines[1 + 2 * p];
    EXPECT_EQ(whole[0], "1");
    EXPECT_EQ(split[0], "2");
    for (size_t c : {1u, 2u, 6u, 7u, 8u, 11u, 12u}) EXPECT_EQ(split[c], whole[c]) << whole[1] << " column " << c;
    const std::string policy = whole[1];
    EXPECT_EQ(whole[8], "30") << "the steps of the whole launch";
    if (policy == "reactive") {
      EXPECT_GT(std::stol(whole[12]), 0) << "reactive moved no slice: the test would show nothing";
    }
    const std::string a = run_dir(policy, 1), b = run_dir(policy, 2);
    ASSERT_FALSE(a.empty() || b.empty()) << policy;
    const auto trace = semlb::split(slurp(a + "/trace.jsonl"), '\n');
    ASSERT_EQ(trace.size(), 1u + 3u) << "3 events, then the empty field";
    EXPECT_EQ(slurp(b + "/trace.jsonl"), slurp(a + "/trace.jsonl")) << policy;
    EXPECT_EQ(modelled_columns(b + "/" + semlb::engine::rank_times::kFile),
              modelled_columns(a + "/" + semlb::engine::rank_times::kFile))
        << policy;
    EXPECT_EQ(semlb::engine::read_state(b + "/final.h5").hash(), semlb::engine::read_state(a + "/final.h5").hash())
        << policy;
    // the split launch ran as two: the first segment logged its last step, 15, which the unsplit run does not log
    const auto steps_logged = [](const std::string& run_csv) {
      std::vector<std::string> s;
      for (const auto& line : semlb::split(slurp(run_csv), '\n')) s.push_back(semlb::split(line + ",", ',')[0]);
      return s;
    };
    EXPECT_EQ(steps_logged(b + "/run.csv"), (std::vector<std::string>{"step", "15", "30", ""}))
        << slurp(b + "/run.csv");
    EXPECT_EQ(steps_logged(a + "/run.csv"), (std::vector<std::string>{"step", "30", ""})) << slurp(a + "/run.csv");
  }
}

// `segments` is refused before anything runs when it is not an integer >= 1 or does not divide the steps; a failed
// segment fails its row, naming the segment, and no row is written for it.
TEST(MpiRunners, EndToEndSegmentsAreCheckedAndAFailedSegmentIsNamed) {
  const auto dir = fresh_dir("mpi_end_to_end_segments_bad");
  const std::string head = "name: e2e\nrunner: mpi_end_to_end\noutput: e2e/load_balance.csv\nset:\n  scene: " +
                           source("scenes/epidermis.yaml") + "\n  ranks: 2\n  cells: 60\n  steps: 30\n";
  for (const auto& [value, want] : std::vector<std::pair<std::string, std::string>>{
           {"4", "m.yaml:9: field 'segments': 4 segments do not divide the 30 steps"},
           {"0", "m.yaml:9: field 'segments': '0' is outside"},
           {"1.5", "m.yaml:9: field 'segments': '1.5' is not an integer"}}) {
    write(dir + "/m.yaml", head + "  segments: " + value + "\n");
    fs::remove_all(dir + "/out");
    const auto r = run(within(60) + semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_NE(r.out.find(want), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir + "/out")) << value;
  }
  // a scene that fails at its first step fails segment 1 of 2, and the sweep writes no row
  write(dir + "/m.yaml", head + "  segments: 2\n  scene.time.max_displacement: 1e-9\n");
  fs::remove_all(dir + "/out");
  const auto r = run(within(120) + semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  EXPECT_NE(r.rc, 0) << r.out;
  EXPECT_NE(r.out.find("MPI launch failed in segment 1 of 2 (steps 0-15)"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out/e2e/load_balance.csv"));
  const auto partial = semlb::split(slurp(dir + "/out/e2e/load_balance.csv.partial"), '\n');
  EXPECT_EQ(partial.size(), 2u) << "the header alone";
}

// The other MPI runners split a launch the same way: mpi_intervals' rows (per interval and rank, modelled times in
// work units) of a 2-segment launch are the unsplit launch's, the intervals of both segments in order.
TEST(MpiRunners, IntervalRowsOfASplitLaunchAreTheUnsplitOnes) {
  const auto dir = fresh_dir("mpi_intervals_segments");
  std::string text = engine_manifest(
      "  segments: [1, 2]\n", "  policy: reactive\n  reactive.tau: 0.001\n  scene.decomposition.timing: modelled\n");
  text.replace(text.find("mpi_sim"), 7, "mpi_intervals");
  text.replace(text.find("steps: 20"), 9, "steps: 30");
  write(dir + "/m.yaml", text);
  const auto r = run(within(300) + semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto lines = semlb::split(slurp(dir + "/out/engine.csv"), '\n');
  ASSERT_EQ(lines.at(0), "segments,step,rank,compute_s,imbalance,moved_slices");
  std::vector<std::string> whole, split;
  for (size_t i = 1; i < lines.size(); ++i)
    if (!lines[i].empty()) (lines[i].rfind("1,", 0) == 0 ? whole : split).push_back(lines[i].substr(2));
  ASSERT_EQ(whole.size(), 3u * 2u) << "3 events x 2 ranks";
  EXPECT_EQ(split, whole);
  EXPECT_EQ(semlb::split(whole.back(), ',')[0], "30");
  long moved = 0;
  for (const auto& l : whole) moved += std::stol(semlb::split(l, ',')[4]);
  EXPECT_GT(moved, 0) << "reactive moved no slice: the test would show nothing";
}
