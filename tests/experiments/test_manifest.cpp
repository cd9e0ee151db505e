// Manifests: cartesian expansion, profiles, overrides, and line-accurate errors.
#include <gtest/gtest.h>

#include "common/errors.hpp"
#include "experiments/manifest.hpp"
#include "experiments/runner.hpp"
#include "../run_command.hpp"

using namespace semlb;
using namespace semlb::experiments;

namespace {
std::string manifest(const std::string& text) {
  const auto path = test::fresh_dir("manifest") + "/m.yaml";
  test::write(path, text);
  return path;
}
const char* kBase = R"(name: demo
runner: surrogate
output: demo.csv
axes:
  policy: [static, reactive]
  ranks: [2, 4]
  seed: "9000-9002"
set:
  events: 10
profiles:
  small: {}
  paper:
    axes: {seed: "9000-9009"}
    set: {events: 100}
)";
std::string error_of(const std::string& text, const std::string& profile = "", std::vector<std::string> sets = {}) {
  try {
    load_manifest(manifest(text), profile, sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Manifest, ExpandsTheCartesianProductLastAxisFastest) {
  const auto m = load_manifest(manifest(kBase), "", {});
  EXPECT_EQ(m.profile, "small");
  const auto jobs = m.expand();
  ASSERT_EQ(jobs.size(), 2u * 2u * 3u);
  EXPECT_EQ(jobs[0].find("policy")->value, "static");
  EXPECT_EQ(jobs[0].find("seed")->value, "9000");
  EXPECT_EQ(jobs[1].find("seed")->value, "9001");
  EXPECT_EQ(jobs[3].find("ranks")->value, "4");
  EXPECT_EQ(jobs[6].find("policy")->value, "reactive");
  EXPECT_EQ(jobs[0].find("events")->value, "10");
  EXPECT_EQ(jobs[0].find("policy")->line, 5);
}

TEST(Manifest, ProfilesAndOverrides) {
  const auto paper = load_manifest(manifest(kBase), "paper", {});
  EXPECT_EQ(paper.expand().size(), 2u * 2u * 10u);
  EXPECT_EQ(paper.fixed.at("events").value, "100");
  const auto o = load_manifest(manifest(kBase), "", {"ranks=16", "events=5", "policy=holt,oracle", "seed=1-2"});
  const auto jobs = o.expand();
  ASSERT_EQ(jobs.size(), 2u * 1u * 2u);
  EXPECT_EQ(jobs[0].find("ranks")->value, "16");
  EXPECT_EQ(jobs[0].find("events")->value, "5");
  EXPECT_EQ(jobs[3].find("policy")->value, "oracle");
}

TEST(Manifest, ErrorsNameFileLineAndField) {
  EXPECT_NE(error_of(std::string(kBase) + "colour: red\n").find(":15: field 'colour': unknown manifest key"),
            std::string::npos);
  EXPECT_NE(error_of(kBase, "huge").find("no profile 'huge'"), std::string::npos);
  EXPECT_NE(error_of("name: x\nrunner: surrogate\n").find("field 'output': missing"), std::string::npos);
  EXPECT_NE(error_of("name: [x\n").find("m.yaml:2: YAML syntax error"), std::string::npos);
  std::string bad_range = kBase;
  bad_range.replace(bad_range.find("9000-9002"), 9, "9002-9000");
  EXPECT_NE(error_of(bad_range).find(":7: field 'axes.seed'"), std::string::npos);
  EXPECT_NE(error_of(kBase, "", {"nokey"}).find("--set: 'nokey' is not KEY=VALUE"), std::string::npos);
}

// A key given as an axis and as a setting in one block is refused at the setting's line (the row would record
// the axis value but run the setting's); a profile's setting replaces the manifest's axis, as --set does.
TEST(Manifest, AKeyIsAnAxisOrASettingNotBoth) {
  std::string both = kBase;
  both.replace(both.find("  events: 10\n"), 13, "  events: 10\n  ranks: 8\n");
  EXPECT_NE(error_of(both).find(":10: field 'set.ranks': 'ranks' is also an axis (line 6): give it in one place"),
            std::string::npos)
      << error_of(both);
  std::string profile_set = kBase;
  profile_set.replace(profile_set.find("    set: {events: 100}"), 22, "    set: {events: 100, ranks: 8}");
  const auto m = load_manifest(manifest(profile_set), "paper", {});
  const auto jobs = m.expand();
  ASSERT_EQ(jobs.size(), 2u * 10u);  // the ranks axis is gone
  for (const auto& j : jobs) EXPECT_EQ(j.find("ranks")->value, "8");
}

TEST(Manifest, RunnerChecksSettingsBeforeRunning) {
  std::string text = kBase;
  text.replace(text.find("[static, reactive]"), 18, "[static, reactiv]");
  const auto m = load_manifest(manifest(text), "", {});
  const auto runner = make_runner(m.runner, m.path);
  try {
    for (const auto& j : m.expand()) runner->check(j, m.path, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":5: field 'policy': unknown policy 'reactiv'"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(make_runner("warp", m.path), InputError);
}

namespace {
const char* kGroups = R"(name: demo
runner: surrogate
output: demo.csv
axes:
  ranks: [2, 4]
  seed: "9000-9001"
groups:
  - policy: [reactive]
    reactive.tau: [0.02, 0.2]
    reactive.alpha: [0.5]
  - policy: [all_tensor]
    all_tensor.gamma: [4, 8, 16]
  - policy: [gru]
set:
  events: 10
profiles:
  small: {}
  one: {groups: [{policy: [static]}]}
)";
}  // namespace

TEST(Manifest, GroupsExpandToTheUnionOfTheirProducts) {
  const auto m = load_manifest(manifest(kGroups), "", {});
  const auto jobs = m.expand();
  ASSERT_EQ(jobs.size(), (2u + 3u + 1u) * 2u * 2u);
  EXPECT_EQ(jobs[0].find("policy")->value, "reactive");
  EXPECT_EQ(jobs[0].find("reactive.tau")->value, "0.02");
  EXPECT_EQ(jobs[1].find("seed")->value, "9001");  // the shared axes vary fastest
  EXPECT_EQ(jobs[4].find("reactive.tau")->value, "0.2");
  EXPECT_EQ(jobs[8].find("policy")->value, "all_tensor");
  EXPECT_EQ(jobs[8].find("reactive.tau"), nullptr);  // a row lacks the other groups' axes
  EXPECT_EQ(jobs[12].find("all_tensor.gamma")->value, "8");
  EXPECT_EQ(jobs[20].find("policy")->value, "gru");
  EXPECT_EQ(jobs[20].find("all_tensor.gamma"), nullptr);
  EXPECT_EQ(jobs[23].find("events")->value, "10");
  EXPECT_EQ(m.axis_names(), (std::vector<std::string>{"ranks", "seed", "policy", "reactive.tau", "reactive.alpha",
                                                      "all_tensor.gamma"}));
  // --set replaces a group's axis wherever it appears, and a shared axis as before
  const auto o = load_manifest(manifest(kGroups), "", {"reactive.tau=0.5", "ranks=8", "policy=gru"});
  const auto few = o.expand();
  ASSERT_EQ(few.size(), (1u + 3u + 1u) * 1u * 2u);
  EXPECT_EQ(few[0].find("reactive.tau")->value, "0.5");
  EXPECT_EQ(few[0].find("reactive.tau")->source, "--set reactive.tau");
  EXPECT_EQ(few[0].find("policy")->value, "gru");
  EXPECT_EQ(few[9].find("ranks")->value, "8");
  // a profile's groups replace the manifest's
  EXPECT_EQ(load_manifest(manifest(kGroups), "one", {}).expand().size(), 1u * 2u * 2u);
}

TEST(Manifest, GroupErrorsNameFileLineAndField) {
  std::string shared = kGroups;
  shared.replace(shared.find("    reactive.alpha"), 0, "    seed: [1]\n");
  EXPECT_NE(error_of(shared).find("m.yaml:10: field 'groups[0].seed': is also a shared axis"), std::string::npos)
      << error_of(shared);
  EXPECT_NE(error_of(std::string(kBase) + "groups: {policy: [static]}\n")
                .find(":15: field 'groups': must be a non-empty list"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(kBase) + "groups:\n  - [static]\n")
                .find(":16: field 'groups[0]': must be a non-empty mapping"),
            std::string::npos);
  std::string empty = kGroups;
  empty.replace(empty.find("[4, 8, 16]"), 10, "[]");
  EXPECT_NE(error_of(empty).find(":12: field 'groups[1].all_tensor.gamma': axis has no values"), std::string::npos)
      << error_of(empty);
}

// `launches: N` repeats every row N times launch-major: launch 1 of every policy (all groups), then launch 2.
TEST(Manifest, LaunchesInterleaveEveryRowLaunchByLaunch) {
  const std::string text = std::string(kGroups) + "launches: 3\n";
  const auto m = load_manifest(manifest(text), "", {"ranks=4", "seed=9000"});
  const auto jobs = m.expand();
  const size_t rows = 2 + 3 + 1;  // reactive x 2 taus, all_tensor x 3 gammas, gru
  ASSERT_EQ(jobs.size(), 3 * rows);
  EXPECT_EQ(m.axis_names().front(), "launch");
  for (size_t i = 0; i < jobs.size(); ++i) {
    EXPECT_EQ(jobs[i].settings.front().first, "launch");
    EXPECT_EQ(jobs[i].find("launch")->value, std::to_string(i / rows + 1)) << i;
    // the same row order within each launch
    EXPECT_EQ(jobs[i].find("policy")->value, jobs[i % rows].find("policy")->value) << i;
  }
  EXPECT_EQ(jobs[0].find("policy")->value, "reactive");
  EXPECT_EQ(jobs[rows - 1].find("policy")->value, "gru");
  EXPECT_EQ(jobs[rows].find("policy")->value, "reactive");  // launch 2 starts over
  EXPECT_EQ(jobs[0].find("launch")->line, 19);
  EXPECT_EQ(load_manifest(manifest(text), "", {"launches=5"}).expand().size(), 5 * rows * 2 * 2);
  EXPECT_EQ(load_manifest(manifest(kGroups), "", {}).axis_names().front(), "ranks");  // no launches: no axis
  EXPECT_NE(error_of(std::string(kGroups) + "launches: 0\n").find("m.yaml:19: field 'launches':"), std::string::npos);
  EXPECT_NE(error_of(std::string(kGroups) + "launches: 2x\n").find("m.yaml:19: field 'launches':"), std::string::npos);
  EXPECT_NE(error_of(text, "", {"launch=2"}).find("may not set 'launch' itself"), std::string::npos);
}
