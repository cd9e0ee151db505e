// The mpi_sim / mpi_intervals runners: POLICY.KEY parameters, load-time refusals, typed values, rank_times.csv.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <map>

#include "../run_command.hpp"
#include "common/text_io.hpp"
#include "engine/run/driver.hpp"

using namespace semlb::test;
namespace fs = std::filesystem;

namespace {
// Two rows of 60 cells on 2 ranks, 20 steps: seconds each.
std::string engine_manifest(const std::string& axes, const std::string& set) {
  return "name: engine\nrunner: mpi_sim\noutput: engine.csv\naxes:\n" + axes + "set:\n  scene: " +
         source("scenes/epidermis.yaml") + "\n  ranks: 2\n  cells: 60\n  steps: 20\n  rebalance_every: 10\n" + set;
}
}  // namespace

// holt.alpha / holt.beta reach holt's rows as decomposition.params (the engine builds holt with them) and are
// left out of static's rows (which would refuse them as unknown parameters), as in the surrogate runner.
TEST(MpiRunners, PolicyParametersReachTheRowsOfTheirPolicyOnly) {
  const auto dir = fresh_dir("mpi_policy_params");
  write(dir + "/m.yaml", engine_manifest("  policy: [static, holt]\n", "  holt.alpha: 0.3\n  holt.beta: 0.1\n"));
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --keep-runs --results " + dir + "/out");
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
  EXPECT_NE(r.out.find("m.yaml:12: field 'holt.*': policy parameter 'alpha': '7' is outside (0, 1]"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

// A policy that needs the true work of the next interval (PolicyNeeds::true_work) cannot be fed by a
// simulation: the sweep refuses the manifest before its first row runs, naming where the policy was set.
TEST(MpiRunners, OraclePoliciesAreRefusedBeforeAnythingRuns) {
  const auto dir = fresh_dir("mpi_oracle");
  auto refused = [&](const std::string& manifest_text, const std::string& sets, const std::string& want) {
    write(dir + "/m.yaml", manifest_text);
    fs::remove_all(dir + "/out");
    const auto r = run(within(60) + semlb_bin() + " sweep " + dir + "/m.yaml --quiet --keep-runs --results " + dir + "/out" + sets);
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
  EXPECT_NE(again.out.find("m.yaml:11: field 'rebalance_every': 'often' is not an integer"), std::string::npos) << again.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

// rank_times.csv is written in engine::rank_times::kColumns' order, and mpi_intervals copies its columns by name.
TEST(MpiRunners, RankTimesColumnsAreTheDeclaredOnes) {
  const auto dir = fresh_dir("mpi_intervals");
  std::string text = engine_manifest("  policy: [reactive]\n", "  scene.decomposition.timing: modelled\n");
  text.replace(text.find("mpi_sim"), 7, "mpi_intervals");
  write(dir + "/m.yaml", text);
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --keep-runs --results " + dir + "/out");
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
  for (size_t i = 1; i + 1 < times.size(); ++i) {  // same step, rank, imbalance, moved slices; compute_s 0 under --no-timing
    const auto f = semlb::split(times[i], ','), g = semlb::split(csv[i], ',');
    EXPECT_EQ(g, (std::vector<std::string>{"reactive", f[0], f[1], "0", f[5], f[6]})) << csv[i];
  }
}
