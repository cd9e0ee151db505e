// The semlb binary: help, bad input (exit 2, one line, no output), determinism, replay == rollout.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <sstream>
#include <vector>

#include "common/text_io.hpp"
#include "../run_command.hpp"

using namespace semlb::test;
namespace fs = std::filesystem;

namespace {
void expect_bad_input(const std::string& args, const std::string& message, const std::string& no_file = "") {
  const auto r = run(semlb_bin() + " " + args);
  EXPECT_EQ(r.rc, 2) << args << "\n" << r.out;
  EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  if (!no_file.empty()) {
    EXPECT_FALSE(fs::exists(no_file)) << no_file;
  }
}
}  // namespace

TEST(Cli, HelpForEverySubcommand) {
  // Every subcommand the top-level help lists (sim and train included), and at least the documented ones.
  const auto top = run(semlb_bin() + " --help");
  ASSERT_EQ(top.rc, 0) << top.out;
  std::istringstream lines(top.out.substr(top.out.find("Subcommands:")));
  std::string line;
  std::vector<std::string> subs;
  while (std::getline(lines, line))
    if (line.rfind("  ", 0) == 0 && line.size() > 2 && line[2] != ' ')
      subs.push_back(line.substr(2, line.find(' ', 2) - 2));
  for (const char* must : {"surrogate", "replay", "sweep", "bench", "sim"})
    EXPECT_NE(std::find(subs.begin(), subs.end(), must), subs.end()) << must << " missing from\n" << top.out;
  for (const auto& sub : subs) {
    const auto r = run(semlb_bin() + " " + sub + " --help");
    EXPECT_EQ(r.rc, 0) << sub;
    EXPECT_NE(r.out.find("Usage: " + semlb_bin() + " " + sub), std::string::npos) << sub << "\n" << r.out;
  }
}

TEST(Cli, BadInputExitsTwoWithOneLineAndNoOutput) {
  const auto dir = fresh_dir("cli_bad");
  const std::string out = " --out " + dir + "/o";
  expect_bad_input("surrogate --policies static,warp" + out, "unknown policy 'warp'", dir + "/o/controller_eval.csv");
  expect_bad_input("surrogate --policies static --seeds 9005-9000" + out, "--seeds: '9005-9000'",
                   dir + "/o/controller_eval.csv");
  expect_bad_input("surrogate --policies static --ranks 0" + out, "ranks", dir + "/o/controller_eval.csv");
  expect_bad_input("surrogate --policies gru --weights " + dir + "/none.h5" + out, "none.h5: no such file");
  expect_bad_input("surrogate --policies static --scenario slices=300 --scenario slices=400" + out,
                   "--scenario slices: given twice (also --scenario slices)", dir + "/o/controller_eval.csv");
  expect_bad_input("surrogate --policies static --param reactive.tua=1" + out, "no parameter 'tua'");
  expect_bad_input("surrogate --policies static --events -3" + out, "--events");
  expect_bad_input("surrogate --policies static --frobnicate" + out, "frobnicate");
  expect_bad_input("warp", "warp");
  write(dir + "/t.jsonl",
        "{\"event\":0,\"slices\":8,\"min_width\":2,\"boundaries\":[4],\"times\":[1,1]}\n\n"
        "{\"event\":1,\"slices\":8,\"min_width\":2,\"boundaries\":[4],\"times\":[1]}\n");
  expect_bad_input("replay --policy reactive --trace " + dir + "/t.jsonl",
                   "t.jsonl:3: field 'boundaries': event 1: boundaries has 1");
  expect_bad_input("replay --policy reactive --trace " + dir + "/missing.jsonl", "missing.jsonl: cannot open trace");
}

// Validation errors name their source (the flag or --set KEY), and nothing is created before every job is
// checked: not the CSV, not its .partial, not the results directory.
TEST(Cli, ErrorsNameTheirSourceAndLeaveNoPartialFile) {
  const auto dir = fresh_dir("cli_source");
  expect_bad_input(
      "sweep " + source("experiments/controller_eval.yaml") + " --quiet --set ranks=2000 --results " + dir + "/r",
      "--set ranks: ranks = 2000 must be in [1, ", dir + "/r");
  expect_bad_input(
      "sweep " + source("experiments/controller_eval.yaml") + " --quiet --set events=1e3 --results " + dir + "/r",
      "--set events: '1e3' is not an integer", dir + "/r");
  expect_bad_input(
      "sweep " + source("experiments/controller_eval.yaml") + " --quiet --set ranks=2.5 --results " + dir + "/r",
      "--set ranks: '2.5' is not an integer", dir + "/r");
  expect_bad_input("surrogate --policies static --ranks 2,2000 --quiet --out " + dir + "/o",
                   "--ranks: ranks = 2000 must be in [1, ", dir + "/o");
  expect_bad_input("surrogate --policies reactive --param reactive.alpha=0 --quiet --out " + dir + "/o",
                   "--param reactive.alpha: policy parameter 'alpha': '0' is outside (0, 2)", dir + "/o");
  expect_bad_input("surrogate --policies holt --param holt.beta=0.5x --quiet --out " + dir + "/o",
                   "--param holt.beta: policy parameter 'beta': '0.5x' is not a number", dir + "/o");
  expect_bad_input("surrogate --policies static --seeds 9000.0 --quiet --out " + dir + "/o",
                   "--seeds: '9000.0': '9000.0' is not an integer", dir + "/o");
  expect_bad_input("sim --quiet --scene " + source("scenes/epidermis.yaml") +
                       " --set 'effects.noise={diffusoin: 0.1}' --out " + dir + "/s",
                   "--set effects.noise: field 'effects.noise.diffusoin': unknown setting", dir + "/s");
  expect_bad_input("sim --quiet --scene " + source("tests/data/mm_domain.yaml") + " --out " + dir + "/s",
                   "mm_domain.yaml:5: field 'domain.hi': '0.15mm' is not a number", dir + "/s");
}

// Input that yaml-cpp alone would accept silently: a duplicate key (it keeps the first), an integer with a
// leading zero (octal to a YAML 1.1 reader), a --set hidden by its flag, a misspelt decomposition setting on
// one device (the section is read only under mpirun otherwise).
TEST(Cli, AmbiguousInputIsRefused) {
  const auto dir = fresh_dir("cli_ambiguous");
  const std::string scene = slurp(source("scenes/mechanics.yaml"));
  write(dir + "/dup.yaml", scene + "seed: 2\n");
  expect_bad_input("sim --quiet --scene " + dir + "/dup.yaml --out " + dir + "/s", "dup.yaml:", dir + "/s");
  expect_bad_input("sim --quiet --scene " + dir + "/dup.yaml --out " + dir + "/s",
                   "field 'seed': duplicate key (first at line ", dir + "/s");
  write(dir + "/dup_nested.yaml", scene + "decomposition: {policy: static, policy: reactive}\n");
  expect_bad_input("sim --quiet --scene " + dir + "/dup_nested.yaml --out " + dir + "/s",
                   "field 'decomposition.policy': duplicate key", dir + "/s");
  const std::string sim =
      "sim --scene " + source("scenes/mechanics.yaml") + " --set tissue.cells=20 --quiet --out " + dir + "/s";
  expect_bad_input(sim + " --set seed=010", "--set seed: '010' has a leading zero", dir + "/s");
  expect_bad_input(sim + " --steps 010", "--steps: '010' has a leading zero", dir + "/s");
  expect_bad_input(sim + " --steps 5 --set time.steps=abc", "--steps: time.steps is also given by --set", dir + "/s");
  expect_bad_input(sim + " --backend serial --set 'backend={name: cpu-binned}'",
                   "--backend: backend.name is also given by --set backend; give it once", dir + "/s");
  expect_bad_input(sim + " --backend serial --set backend=5", "--backend: backend.name is also given by --set backend",
                   dir + "/s");
  // a --set whose path the scene lacks: the maps it makes on the way are blamed on it, not on the scene file
  expect_bad_input(sim + " --set backend.cpu_binned.threads=1",
                   "--set backend.cpu_binned.threads: field 'backend.cpu_binned': is not a backend", dir + "/s");
  expect_bad_input(sim + " --set backend.threads.x=1",
                   "--set backend.threads.x: field 'backend.threads': ", dir + "/s");
  expect_bad_input(sim + " --set backend..threads=1", "--set backend..threads: an empty key in the path", dir + "/s");
  // a --set into the backend's own map that the key beside name (in the file) overrides would do nothing
  write(dir + "/beside.yaml",
        std::regex_replace(scene, std::regex("\nbackend:[^\n]*"),
                           "\nbackend: {name: cpu-binned, threads: 1, cpu-binned: {threads: 2}}"));
  expect_bad_input(
      "sim --quiet --scene " + dir + "/beside.yaml --set tissue.cells=20 --out " + dir +
          "/s --set backend.cpu-binned.threads=3",
      "--set backend.cpu-binned.threads: has no effect: backend.threads (" + dir + "/beside.yaml:", dir + "/s");
  ASSERT_EQ(run(semlb_bin() + " sim --quiet --scene " + dir + "/beside.yaml --set tissue.cells=20 --steps 1 --out " +
                dir + "/b --set backend.threads=3")
                .rc,
            0);  // the key beside name: it overrides, as documented
  expect_bad_input(sim + " --set decomposition.polcy=reactive", "--set decomposition.polcy: unknown setting",
                   dir + "/s");
  expect_bad_input(sim + " --set decomposition.policy=warp", "--set decomposition.policy: ", dir + "/s");
  write(dir + "/m.yaml", "name: m\nname: n\nrunner: surrogate\n");
  expect_bad_input("sweep " + dir + "/m.yaml --quiet --results " + dir + "/r",
                   "m.yaml:2: field 'name': duplicate key (first at line 1)", dir + "/r");
  ASSERT_EQ(run(semlb_bin() + " " + sim + " --steps 0 --set decomposition.policy=reactive").rc, 0);  // valid: accepted
  ASSERT_EQ(run(semlb_bin() + " sim --quiet --scene " + source("scenes/mechanics.yaml") +
                " --set tissue.cells=20 --out " + dir + "/t --steps 1 --set 'time={dt: 0.01}'")
                .rc,
            0)
      << "--steps beside a --set of a time map that does not hold steps";
}

// Integer flags go through the one strict parser: hex, '+', negative counts and trailing text are refused.
TEST(Cli, IntegerFlagsAreStrict) {
  const auto dir = fresh_dir("cli_integers");
  const std::string sim =
      "sim --scene " + source("scenes/mechanics.yaml") + " --set tissue.cells=20 --quiet --out " + dir + "/s";
  expect_bad_input(sim + " --steps 0x10", "--steps: '0x10' is not an integer", dir + "/s");
  expect_bad_input(sim + " --steps +7", "--steps: '+7' is not an integer", dir + "/s");
  expect_bad_input(sim + " --steps -1", "--steps: '-1' is outside [0, ", dir + "/s");
  expect_bad_input(sim + " --seed -5", "--seed: '-5' is outside [0, ", dir + "/s");
  expect_bad_input(sim + " --device -1", "--device: '-1' is outside [0, 1024]", dir + "/s");
  expect_bad_input("surrogate --policies static --events 0x5 --quiet --out " + dir + "/o",
                   "--events: '0x5' is not an integer", dir + "/o");
  expect_bad_input("surrogate --policies static --jobs 0 --quiet --out " + dir + "/o", "--jobs: '0' is outside [1, ",
                   dir + "/o");
}

TEST(Cli, SameSeedsGiveTheSameCsv) {
  const auto dir = fresh_dir("cli_det");
  const std::string args =
      " surrogate --policies static,reactive,persistence,holt,oracle --ranks 2,8 --seeds 9000-9002 "
      "--events 30 --no-timing --quiet --out ";
  ASSERT_EQ(run(semlb_bin() + args + dir + "/a").rc, 0);
  ASSERT_EQ(run(semlb_bin() + args + dir + "/b --jobs 2").rc, 0);
  const auto a = slurp(dir + "/a/controller_eval.csv");
  EXPECT_EQ(a, slurp(dir + "/b/controller_eval.csv"));
  EXPECT_EQ(a.substr(0, a.find('\n')),
            "policy,ranks,seed,events,slices,min_width,mean_imbalance,migration,mean_max_over_mean,"
            "first_quarter_imbalance,last_quarter_imbalance,us_per_decision");
  EXPECT_EQ(std::count(a.begin(), a.end(), '\n'), 1 + 5 * 2 * 3);
}

TEST(Cli, ReplayOfADumpedTraceReproducesTheRollout) {
  const auto dir = fresh_dir("cli_replay");
  ASSERT_EQ(run(semlb_bin() +
                " surrogate --policies reactive,holt,persistence,oracle --ranks 4 --seeds 9001 --events 40 "
                "--dump-traces --quiet --out " +
                dir)
                .rc,
            0);
  for (const char* policy : {"reactive", "holt", "persistence", "oracle"}) {
    const std::string trace = dir + "/traces/" + policy + "_P4_s9001.jsonl";
    ASSERT_TRUE(fs::exists(trace)) << trace;
    const auto r = run(semlb_bin() + " replay --policy " + policy + " --trace " + trace);
    ASSERT_EQ(r.rc, 0) << r.out;
    std::istringstream replayed(r.out), recorded(slurp(trace));
    std::string got, want;
    int events = 0;
    while (std::getline(recorded, want)) {
      ASSERT_TRUE(std::getline(replayed, got));
      const auto d = want.find("\"decision\":");
      const std::string decision = want.substr(d + 11, want.find(']', d) - d - 10);
      EXPECT_NE(got.find("\"boundaries\":" + decision), std::string::npos) << policy << " event " << events;
      ++events;
    }
    EXPECT_EQ(events, 40);
  }
}

// semlb surrogate and semlb sweep end with what they measured per policy and P: means, "mean ± sd" over the seeds,
// the seeds counted; --quiet leaves the last line only.
TEST(Cli, SurrogateAndSweepEndWithATableOfWhatWasMeasured) {
  const auto dir = fresh_dir("cli_tables");
  const auto r =
      run(semlb_bin() + " surrogate --policies static,reactive --ranks 2,4 --seeds 9000-9002 --events 20 --out " + dir +
          "/s");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\npolicy +\\| P \\| imbalance % +\\| migration +\\| n\n"))) << r.out;
  for (const char* row :
       {"static +\\| 2 \\| [0-9.]+ ± [0-9.]+ +\\| 0 ± 0 +\\| 3\n", "static +\\| 4 \\| ",
        "reactive \\| 2 \\| [0-9.]+ ± [0-9.]+ +\\| [0-9.]+ ± [0-9.]+ +\\| 3\n", "reactive \\| 4 \\| "})
    EXPECT_TRUE(std::regex_search(r.out, std::regex(std::string("\n") + row))) << row << "\n" << r.out;
  EXPECT_NE(r.out.find("\nwrote " + dir + "/s/controller_eval.csv (12 rows)\n"), std::string::npos) << r.out;
  const auto q =
      run(semlb_bin() + " surrogate --policies static --ranks 2 --seeds 9000 --events 5 --quiet --out " + dir + "/q");
  ASSERT_EQ(q.rc, 0) << q.out;
  EXPECT_EQ(q.out.find("imbalance %"), std::string::npos) << q.out;
  // Knob columns (POLICY.KEY) name each row's setting; of several settings of a policy at a P the line shows the one
  // with the least imbalance and says of how many; a policy without knobs runs its default.
  const auto k = run(semlb_bin() + " sweep " + source("experiments/controller_eval_engine.yaml") + " --results " + dir +
                     "/k --set ranks=2 --set seed=0");
  ASSERT_EQ(k.rc, 0) << k.out;
  EXPECT_TRUE(std::regex_search(
      k.out, std::regex("\npolicy +\\| P \\| setting +\\| imbalance % +\\| migration +\\| loop s +\\| n\n")))
      << k.out;
  EXPECT_TRUE(std::regex_search(k.out, std::regex("\nstatic +\\| 2 \\| default +\\| "))) << k.out;
  EXPECT_TRUE(std::regex_search(
      k.out, std::regex("\nreactive +\\| 2 \\| tau=[0-9.]+ alpha=[0-9.]+ \\(least imbalance % of [0-9]+\\) +\\| ")))
      << k.out;
  const auto w = run(semlb_bin() + " sweep " + source("experiments/controller_eval.yaml") + " --results " + dir +
                     "/w --set policy=static,gru --set ranks=2 --set seed=9000-9001 --set events=10");
  ASSERT_EQ(w.rc, 0) << w.out;
  EXPECT_TRUE(std::regex_search(w.out, std::regex("\npolicy \\| P \\| imbalance % +\\| migration +\\| n\n"))) << w.out;
  EXPECT_TRUE(
      std::regex_search(w.out, std::regex("\ngru    \\| 2 \\| [0-9.]+ ± [0-9.]+ +\\| [0-9.]+ ± [0-9.]+ +\\| 2\n")))
      << w.out;
}

TEST(Cli, BenchPrintsATableRowPerPolicy) {
  const auto r = run(semlb_bin() + " bench policies --ranks 4 --events 10 --repeats 1");
  ASSERT_EQ(r.rc, 0) << r.out;
  for (const char* p : {"static", "reactive", "persistence", "holt", "gru", "oracle", "foresight"})
    EXPECT_NE(r.out.find(std::string("\n") + p + " "), std::string::npos) << p;
}

TEST(Cli, VersionNamesTheGitRevision) {
  const auto r = run(semlb_bin() + " --version");
  ASSERT_EQ(r.rc, 0) << r.out;
  // "semlb 0.1.0 (git 865c72d1a2b3)": the project version and the revision CMake configured with
  EXPECT_EQ(r.out.rfind("semlb 0.1.0 (git ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find(")"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

TEST(Cli, ListPrintsTheRegistries) {
  const auto types = run(semlb_bin() + " list cell-types --json");
  ASSERT_EQ(types.rc, 0) << types.out;
  EXPECT_EQ(types.out, "[\"basal\",\"spinous\",\"granular\"]\n");     // by type index, as the state files store them
  const auto fields = run(semlb_bin() + " list cell-fields --json");  // what the effects declare, in name order
  ASSERT_EQ(fields.rc, 0) << fields.out;
  EXPECT_EQ(fields.out, "[\"differentiation.age\",\"division.depth\",\"growth.clock\"]\n");
  // the plug-in kinds among the effects: each a registry of its own, each name an effect
  const auto effects = run(semlb_bin() + " list effects").out;
  for (const auto& [what, want] :
       std::vector<std::pair<std::string, std::string>>{{"pair-terms", "[\"mechanics\",\"relu\"]\n"},
                                                        {"element-terms", "[\"membrane\",\"walls\"]\n"},
                                                        {"fate-rules", "[\"differentiation\"]\n"},
                                                        {"removal-rules", "[\"desquamation\"]\n"}}) {
    const auto r = run(semlb_bin() + " list " + what + " --json");
    ASSERT_EQ(r.rc, 0) << r.out;
    EXPECT_EQ(r.out, want) << what;
    for (const auto& name : semlb::split(run(semlb_bin() + " list " + what).out, '\n')) {
      if (!name.empty()) {
        EXPECT_NE(effects.find(name + "\n"), std::string::npos) << name << " is not an effect";
      }
    }
  }
  // the values of effects.growth.law and effects.division.rule
  EXPECT_EQ(run(semlb_bin() + " list growth-laws --json").out, "[\"clock\"]\n");
  EXPECT_EQ(run(semlb_bin() + " list division-rules --json").out, "[\"long_axis\",\"oriented\"]\n");
  const auto policies = run(semlb_bin() + " list policies");
  ASSERT_EQ(policies.rc, 0) << policies.out;
  for (const char* p : {"static\n", "reactive\n", "persistence\n", "holt\n", "gru\n", "oracle\n", "lazy_oracle\n",
                        "gromacs_dlb\n", "foresight\n", "learned_repartition\n"})
    EXPECT_NE(policies.out.find(p), std::string::npos) << p << policies.out;
  // engine-policies: the policies a simulation runs, the surrogate baselines that need the true work left out
  const auto engine = run(semlb_bin() + " list engine-policies --json");
  ASSERT_EQ(engine.rc, 0) << engine.out;
  EXPECT_EQ(engine.out,
            "[\"all_tensor\",\"gromacs_dlb\",\"gru\",\"holt\",\"hoomd_balance\",\"lammps_shift\","
            "\"learned_repartition\",\"persistence\",\"reactive\",\"static\"]\n");
  for (const char* what : {"effects", "backends", "runners", "launchers"}) {
    const auto r = run(semlb_bin() + " list " + what + " --json");
    EXPECT_EQ(r.rc, 0) << what;
    EXPECT_EQ(r.out.rfind("[\"", 0), 0u) << what << ": " << r.out;
  }
  expect_bad_input("list nothing", "nothing");
  // the kinds come from the catalogue every registry adds itself to (common/registry.hpp listed_kinds)
  const auto kinds = run(semlb_bin() + " list kinds --json");
  ASSERT_EQ(kinds.rc, 0) << kinds.out;
  EXPECT_EQ(kinds.out,
            "[\"backends\",\"cell-fields\",\"cell-types\",\"division-rules\",\"effects\",\"element-terms\","
            "\"engine-policies\",\"fate-rules\",\"growth-laws\",\"launchers\",\"pair-terms\",\"policies\","
            "\"removal-rules\",\"runners\"]\n");
  for (const auto& what : semlb::split(run(semlb_bin() + " list kinds").out, '\n')) {
    if (what.empty()) continue;
    const auto r = run(semlb_bin() + " list " + what + " --json");
    EXPECT_EQ(r.rc, 0) << what << ": " << r.out;
    EXPECT_EQ(r.out.rfind("[\"", 0), 0u) << what << ": " << r.out;
  }
}

TEST(Cli, HelpListsEveryRegisteredName) {
  // surrogate --help names every policy `semlb list policies` prints, sim --help every backend and effect.
  const auto help = run(semlb_bin() + " surrogate --help");
  std::istringstream names(run(semlb_bin() + " list policies").out);
  std::string name;
  int n = 0;
  while (std::getline(names, name)) {
    EXPECT_NE(help.out.find(name), std::string::npos) << name << " missing from surrogate --help";
    ++n;
  }
  EXPECT_GE(n, 12);
  const auto sim = run(semlb_bin() + " sim --help");
  std::istringstream backends(run(semlb_bin() + " list backends").out + run(semlb_bin() + " list effects").out);
  while (std::getline(backends, name))
    EXPECT_NE(sim.out.find(name), std::string::npos) << name << " missing from sim --help";
}
