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
  EXPECT_NE(error_of(std::string(kBase) + "colour: red\n").find(":15: field 'colour': unknown manifest key"), std::string::npos);
  EXPECT_NE(error_of(kBase, "huge").find("no profile 'huge'"), std::string::npos);
  EXPECT_NE(error_of("name: x\nrunner: surrogate\n").find("field 'output': missing"), std::string::npos);
  EXPECT_NE(error_of("name: [x\n").find("m.yaml:2: YAML syntax error"), std::string::npos);
  std::string bad_range = kBase;
  bad_range.replace(bad_range.find("9000-9002"), 9, "9002-9000");
  EXPECT_NE(error_of(bad_range).find(":7: field 'axes.seed'"), std::string::npos);
  EXPECT_NE(error_of(kBase, "", {"nokey"}).find("--set: 'nokey' is not KEY=VALUE"), std::string::npos);
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
    EXPECT_NE(std::string(e.what()).find(":5: field 'policy': unknown policy 'reactiv'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_runner("warp", m.path), InputError);
}
