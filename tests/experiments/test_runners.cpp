// What the runners share (experiments/runner.hpp): every runner refuses a setting it does not take and names it,
// the engine runners' scene (job_scene) names where `scene` was set, and settings families pass the check.
#include <gtest/gtest.h>

#include "../run_command.hpp"
#include "common/errors.hpp"
#include "experiments/runner.hpp"

using namespace semlb;
using namespace semlb::experiments;

namespace {
// A job from (key, value) pairs, the k-th on manifest line k + 2 (as if under `set:`).
Job job_of(const std::vector<std::pair<std::string, std::string>>& kv) {
  Job j;
  long line = 2;
  for (const auto& [k, v] : kv) j.settings.push_back({k, Setting{v, ++line, ""}});
  return j;
}

std::string check_error(const std::string& runner, const Job& job, const RunOptions& o = {}) {
  try {
    make_runner(runner, "m.yaml")->check(job, "m.yaml", o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// Each runner refuses a misspelled setting before anything runs, naming its manifest line and field, with its own
// wording of the runner; the settings before it (each runner's own, and families such as scene.KEY, POLICY.KEY,
// scenario.KEY, time_model.KEY, max_cells.KEY) pass.
TEST(Runners, EveryRunnerRefusesAnUnknownSettingAndNamesIt) {
  const std::vector<std::tuple<std::string, std::vector<std::pair<std::string, std::string>>, std::string>> cases = {
      {"engine_timing", {{"steps", "10"}, {"scene.time.dt", "0.01"}, {"max_cells.serial", "100"}}, "this runner"},
      {"engine_accuracy", {{"hours", "1"}, {"cells", "20"}}, "this runner"},
      {"engine_observables", {{"sample_h", "1"}, {"backend", "serial"}}, "this runner"},
      {"mpi_sim",
       {{"ranks", "2"}, {"segments", "2"}, {"reactive.tau", "0.1"}, {"scene.time.steps", "10"}},
       "this runner"},
      {"mpi_intervals", {{"ranks", "2"}, {"policy", "gru"}}, "this runner"},
      {"mpi_end_to_end", {{"launch", "1"}, {"bind_to", "core"}}, "this runner"},
      {"surrogate",
       {{"policy", "static"}, {"ranks", "2"}, {"seed", "1"}, {"scenario.slices", "40"}, {"holt.alpha", "0.3"}},
       "the surrogate runner"},
      {"workload_eval",
       {{"policy", "static"}, {"coarsen", "2"}, {"time_model.sync_s", "0"}},
       "the workload_eval runner"},
      {"replay_score", {{"policy", "static"}, {"reactive.tau", "0.1"}}, "the replay_score runner"},
  };
  for (const auto& [runner, settings, words] : cases) {
    auto kv = settings;
    kv.push_back({"stpes", "5"});
    const std::string line = std::to_string(kv.size() + 2);
    EXPECT_EQ(check_error(runner, job_of(kv)), "m.yaml:" + line + ": field 'stpes': unknown setting for " + words)
        << runner;
  }
}

// The engine runners and the MPI runners load the job's scene alike: an error in the scene file is prefixed with the
// line of the job's `scene`, and a missing `scene` is named.
TEST(Runners, TheJobsSceneNamesWhereSceneWasSet) {
  const auto dir = test::fresh_dir("runner_scene");
  test::write(dir + "/bad.yaml", test::slurp(test::source("scenes/mechanics.yaml")) + "tiem: 1\n");
  for (const std::string runner : {"engine_timing", "mpi_sim", "mpi_end_to_end"}) {
    std::vector<std::pair<std::string, std::string>> kv = {{"scene", "bad.yaml"}};
    if (runner.rfind("mpi_", 0) == 0) kv.push_back({"ranks", "2"});
    RunOptions o;
    o.base_dir = dir;  // `scene` is relative to the manifest's folder
    const std::string e = check_error(runner, job_of(kv), o);
    EXPECT_EQ(e.rfind("m.yaml:3: field 'scene': " + dir + "/bad.yaml:", 0), 0u) << runner << ": " << e;
    EXPECT_NE(e.find("field 'tiem': unknown setting"), std::string::npos) << runner << ": " << e;
  }
  EXPECT_EQ(check_error("engine_timing", job_of({{"steps", "10"}})),
            "m.yaml: field 'scene': missing (engine runners need a scene file)");
  EXPECT_EQ(check_error("mpi_sim", job_of({{"ranks", "2"}})), "m.yaml: field 'scene': missing");
  // A mistyped override names its own line, not the scene's.
  const std::string e =
      check_error("engine_timing", job_of({{"scene", test::source("scenes/mechanics.yaml")}, {"cells", "many"}}));
  EXPECT_EQ(e.rfind("m.yaml:4: field 'cells': ", 0), 0u) << e;
  // What an override sets that the scene refuses names the override's line, not `scene`'s (nor a --set)
  const std::string scene = test::source("scenes/mechanics.yaml");
  EXPECT_EQ(check_error("engine_timing", job_of({{"scene", scene}, {"scene.effects.mechanics.intra.U0", "x"}})),
            "m.yaml:4: field 'scene.effects.mechanics.intra.U0': 'x' is not a number");
  EXPECT_EQ(check_error("engine_timing", job_of({{"scene", scene}, {"scene.backend.cpu-binned.thread", "1"}})),
            "m.yaml:4: field 'scene.backend.cpu-binned.thread': backend 'cpu-binned' does not use it");
  // every setting a run reads is checked before anything runs (engine::check_scene): the tissue's, the effects', the
  // decomposition's, which a run reads only once it starts
  EXPECT_EQ(check_error("engine_timing", job_of({{"scene", scene}, {"scene.tissue.cels", "1"}})),
            "m.yaml:4: field 'scene.tissue.cels': unknown setting");
  EXPECT_EQ(
      check_error("mpi_sim", job_of({{"scene", scene}, {"ranks", "2"}, {"scene.decomposition.timing", "modeled"}})),
      "m.yaml:5: field 'scene.decomposition.timing': must be measured, modelled or device");
  EXPECT_EQ(check_error("engine_timing", job_of({{"scene", scene}, {"scene.effects.mechanics.inter.U0", "-1"}}))
                .rfind("m.yaml:4: field 'scene.effects.mechanics.inter.U0': ", 0),
            0u);
}

// A scene.KEY setting of a key the job's named setting sets too would win in silence while the CSV's column showed the
// named value (a GPU script's scene.backend.precision=float once turned accuracy_vs_time's double rows into float
// runs labelled double): refused, naming both; scene.KEY of another key passes.
TEST(Runners, SceneKeyBesideTheNamedSettingOfTheSameKeyIsRefused) {
  const std::string scene = test::source("scenes/mechanics.yaml");
  EXPECT_EQ(check_error("engine_accuracy",
                        job_of({{"scene", scene}, {"precision", "double"}, {"scene.backend.precision", "float"}})),
            "m.yaml:5: field 'scene.backend.precision': sets backend.precision, which the job's 'precision' sets too; "
            "give it once (as 'precision')");
  EXPECT_EQ(check_error("engine_timing", job_of({{"scene", scene}, {"cells", "20"}, {"scene.tissue.cells", "30"}})),
            "m.yaml:5: field 'scene.tissue.cells': sets tissue.cells, which the job's 'cells' sets too; give it once "
            "(as 'cells')");
  EXPECT_EQ(
      check_error("engine_timing",
                  job_of({{"scene", scene}, {"cells", "20"}, {"scene.backend.precision", "float"}, {"steps", "1"}})),
      "");
}

TEST(Runners, JobTextAndKey) {
  const Job j = job_of({{"policy", "gru"}, {"ranks", "4"}});
  EXPECT_EQ(j.text("policy", "static"), "gru");
  EXPECT_EQ(j.text("seed", "1"), "1");
  EXPECT_EQ(job_key(j), "policy=gru;ranks=4;");
  EXPECT_NE(job_key(j), job_key(job_of({{"policy", "gru"}, {"ranks", "8"}})));
}
