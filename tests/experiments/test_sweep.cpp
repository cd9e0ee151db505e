// Sweeps end to end through the binary: output, kill -9 + resume (nothing lost or duplicated), torn lines.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "../run_command.hpp"
#include "common/text_io.hpp"

using namespace semlb::test;
namespace fs = std::filesystem;

namespace {
const char* kManifest = R"(name: resume
runner: surrogate
output: sub/resume.csv
axes:
  policy: [static, reactive, holt]
  ranks: [2, 4]
  seed: "9000-9004"
set:
  events: 20
)";
size_t lines(const std::string& s) { return static_cast<size_t>(std::count(s.begin(), s.end(), '\n')); }
}  // namespace

TEST(Sweep, KilledSweepResumesWithoutLosingOrDuplicatingRows) {
  const auto dir = fresh_dir("sweep");
  write(dir + "/m.yaml", kManifest);
  const std::string base = semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --jobs 2 --results ";
  ASSERT_EQ(run(base + dir + "/ref").rc, 0);
  const auto reference = slurp(dir + "/ref/sub/resume.csv");
  EXPECT_EQ(lines(reference), 1u + 30u);
  EXPECT_TRUE(fs::exists(dir + "/ref/sub/resume.manifest.yaml"));

  const auto killed = run("SEMLB_SWEEP_KILL_AFTER=7 " + base + dir + "/cut");
  EXPECT_EQ(killed.rc, 128 + 9) << killed.out;            // SIGKILL
  EXPECT_FALSE(fs::exists(dir + "/cut/sub/resume.csv"));  // no final file from an unfinished sweep
  auto partial = semlb::split(slurp(dir + "/cut/sub/resume.csv.partial"), '\n');
  partial.pop_back();                          // after the last newline
  const size_t finished = partial.size() - 1;  // whole rows of finished jobs (--jobs 2: 7 or 8)
  ASSERT_GE(finished, 7u);
  ASSERT_LT(finished, 30u);
  // Mark one finished row: a resumed sweep keeps it as it is, a sweep that recomputed the job would not.
  // The last column (us_per_decision) is 0 under --no-timing, so the marker cannot occur by chance.
  const std::string original = partial[1];
  const std::string marked = original.substr(0, original.rfind(',')) + ",12345";
  ASSERT_EQ(reference.find(marked), std::string::npos) << marked;
  partial[1] = marked;
  std::string text;
  for (const auto& l : partial) text += l + "\n";
  write(dir + "/cut/sub/resume.csv.partial", text + "holt,4,90");  // and a torn last row
  const auto resumed = run(base + dir + "/cut");
  ASSERT_EQ(resumed.rc, 0) << resumed.out;
  EXPECT_NE(resumed.out.find("(30 jobs, " + std::to_string(finished) + " resumed; 30 rows)"), std::string::npos)
      << resumed.out;
  // .partial's rows start with their settings digest, which OUTPUT leaves out.
  const std::string row = original.substr(original.find(',') + 1), marked_row = marked.substr(marked.find(',') + 1);
  std::string want = reference;
  ASSERT_NE(want.find(row + "\n"), std::string::npos);
  want.replace(want.find(row + "\n"), row.size(), marked_row);
  EXPECT_EQ(slurp(dir + "/cut/sub/resume.csv"), want);  // the finished jobs were reused, the rest computed
  EXPECT_FALSE(fs::exists(dir + "/cut/sub/resume.csv.partial"));

  // A finished sweep is recomputed, not reused: the marked row (now in the final CSV) is replaced.
  const auto again = run(base + dir + "/cut");
  EXPECT_NE(again.out.find("0 resumed"), std::string::npos) << again.out;
  EXPECT_EQ(slurp(dir + "/cut/sub/resume.csv"), reference);
}

TEST(Sweep, BadManifestExitsTwoWithoutOutput) {
  const auto dir = fresh_dir("sweep_bad");
  std::string text = kManifest;
  text.replace(text.find("events: 20"), 10, "events: many");
  write(dir + "/m.yaml", text);
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --results " + dir + "/out");
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.out.find("m.yaml:9: field 'events': 'many' is not an integer"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1);
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

TEST(Sweep, LauncherFlagsAreCheckedBeforeAnythingIsWritten) {
  const auto dir = fresh_dir("sweep_launcher");
  write(dir + "/m.yaml", kManifest);
  const std::string base = semlb_bin() + " sweep " + dir + "/m.yaml --results " + dir + "/out";
  auto r = run(base + " --launcher pbs");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_EQ(r.out, "semlb: --launcher: unknown launcher 'pbs' (known: local, slurm)\n");
  r = run(base + " --partition gpu");  // a Slurm flag without the slurm launcher
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_EQ(r.out, "semlb: --partition: only with --launcher slurm\n");
  r = run(base + " --launcher slurm --dry-run --sbatch-arg='--comment=a#b'");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("--sbatch-arg: '--comment=a#b' may not hold a newline or '#'"), std::string::npos) << r.out;
  // --dry-run prints the batch script for all 30 jobs (no Slurm needed) and writes nothing.
  r = run("env -u SLURM_CONF " + base + " --launcher slurm --dry-run --array-throttle 3 --time 1:00:00");
  EXPECT_EQ(r.rc, 0) << r.out;
  for (const char* l : {"#SBATCH --ntasks=1\n", "#SBATCH --time=1:00:00\n", "%3\n", "30 of 30 jobs",
                        " --task \"${jobs[$SLURM_ARRAY_TASK_ID]}\""})
    EXPECT_NE(r.out.find(l), std::string::npos) << l << "\n" << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

TEST(Sweep, ShippedManifestsParse) {
  for (const auto& entry : fs::directory_iterator(source("experiments")))
    if (entry.path().extension() == ".yaml") {
      // each shipped manifest, shrunk to seconds
      const std::map<std::string, std::string> small = {
          {"training_curve",
           " --set steps=1 --set batch=2 --set events=3 --set validation_seeds=8000 "
           "--set validation_ranks=2 --set validation_events=5"},
          {"single_device", " --set cells=20 --set steps=2 --set backend=serial,cpu-binned"},
          {"effects_cost", " --set cells=20 --set steps=2"},
          {"accuracy_vs_time",
           " --set cells=10 --set hours=0.04 --set dt=0.02 --set cutoff=8.75 --set precision=double"},
          {"accuracy_pair_exp", " --set cells=10 --set hours=0.04 --set dt=0.02"},  // on OpenCL (PoCL in CI)
          {"accuracy_development", " --set cells=9 --set hours=2 --set sample_h=1"},
          {"strong_scaling", " --set cells=60 --set ranks=1 --set steps=20 --set rebalance_every=10"},
          {"load_balance", " --set cells=60 --set ranks=1 --set steps=20 --set rebalance_every=10 --set policy=static"},
          {"rank_balance", " --set cells=60 --set ranks=1 --set steps=20 --set rebalance_every=10 --set policy=static"},
          {"end_to_end",
           " --set cells=20 --set ranks=1 --set steps=20 --set rebalance_every=10 --set policy=static "
           "--set launches=1"},
          {"end_to_end_ranks",
           " --set cells=20 --set ranks=1 --set steps=20 --set rebalance_every=10 --set policy=static"},
          {"replay_score", " --set traces=" + source("results/cpu") + " --set policy=static,foresight"}};
      const auto it = small.find(entry.path().stem().string());
      const std::string sets = it != small.end() ? it->second : " --set seed=9000 --set ranks=2 --set events=2";
      const auto r =
          run(semlb_bin() + " sweep " + entry.path().string() + sets + " --quiet --results " + fresh_dir("shipped"));
      EXPECT_EQ(r.rc, 0) << entry.path() << ": " << r.out;
    }
}

// The mpi_sim runner's times nest: the whole launch >= the time-stepping loop (every log interval summed)
// >= the slowest rank's computation; a loop read from the last log row alone would fall below it.
// --keep-runs keeps each run's files.
TEST(Sweep, MpiSimTimesNestLaunchLoopComputationAndRunsAreKept) {
  const auto dir = fresh_dir("sweep_mpi_times");
  const auto r =
      run(semlb_bin() + " sweep " + source("experiments/strong_scaling.yaml") +
          " --set cells=60 --set ranks=2 --set steps=40 --set rebalance_every=10 --set scene.output.log_every=10"
          " --quiet --keep-runs --results " +
          dir);
  ASSERT_EQ(r.rc, 0) << r.out;
  std::vector<fs::path> kept;
  for (const auto& e : fs::directory_iterator(dir + "/strong_scaling/runs")) kept.push_back(e.path());
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(lines(slurp((kept[0] / "rank_times.csv").string())), 1u + 4u * 2u) << kept[0];
  EXPECT_TRUE(fs::exists(kept[0] / "trace.jsonl"));
  const auto csv = semlb::split(slurp(dir + "/strong_scaling/strong_scaling.csv"), '\n');
  const auto header = semlb::split(csv.at(0), ','), row = semlb::split(csv.at(1), ',');
  std::map<std::string, double> v;
  for (size_t c = 0; c < header.size() && c < row.size(); ++c) v[header[c]] = std::atof(row[c].c_str());
  EXPECT_GT(v.at("compute_s"), 0);
  EXPECT_GE(v.at("wall_s"), v.at("compute_s")) << csv[1];
  EXPECT_GE(v.at("total_s"), v.at("wall_s")) << csv[1];
  EXPECT_EQ(v.at("events"), 4);
}

// Axis groups: each group's parameter axis becomes a column, empty in the rows of the other groups, and each
// row runs with its own group's parameters only.
TEST(Sweep, AxisGroupsWriteEmptyCellsForOtherGroupsAxes) {
  const auto dir = fresh_dir("sweep_groups");
  write(dir + "/m.yaml", R"(name: groups
runner: surrogate
output: g.csv
axes:
  ranks: [4]
  seed: [9000]
groups:
  - policy: [reactive]
    reactive.tau: [0, 100]
  - policy: [all_tensor]
    all_tensor.gamma: [4]
set:
  events: 20
)");
  const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto rows = semlb::split(slurp(dir + "/out/g.csv"), '\n');
  ASSERT_EQ(rows.size(), 1u + 3u + 1u);  // header, 3 rows, after the last newline
  EXPECT_EQ(rows[0].substr(0, rows[0].find(",ranks")), "reactive.tau,all_tensor.gamma,policy");
  EXPECT_EQ(rows[1].rfind("0,,reactive,4,9000,20,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("100,,reactive,4,9000,20,", 0), 0u) << rows[2];
  EXPECT_EQ(rows[3].rfind(",4,all_tensor,4,9000,20,", 0), 0u) << rows[3];
  const auto migration = [](const std::string& row) { return semlb::split(row, ',')[9]; };
  EXPECT_NE(migration(rows[1]), "0");  // tau 0 rebalances ...
  EXPECT_EQ(migration(rows[2]), "0");  // ... tau 100 never does: the row ran with its own group's value
}

// A job still running 2 s after it began is named on stderr with its axes (a line within 2 s of the start
// of every job longer than 5 s); quick jobs print no such line.
TEST(Sweep, LongJobsGetAHeartbeatLineNamingThem) {
  const auto dir = fresh_dir("sweep_heartbeat");
  write(dir + "/m.yaml", R"(name: beat
runner: surrogate
output: beat.csv
axes:
  policy: [static, reactive]
  ranks: [2]
  seed: "1"
set:
  events: 5
)");
  const std::string cmd = semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --jobs 1 --results ";
  const auto slow = run("SEMLB_SWEEP_JOB_DELAY_MS=3500 " + cmd + dir + "/slow");
  ASSERT_EQ(slow.rc, 0) << slow.out;
  EXPECT_NE(slow.out.find("[beat] job 1/2 (policy=static ranks=2 seed=1) running"), std::string::npos) << slow.out;
  EXPECT_NE(slow.out.find("[beat] job 2/2 (policy=reactive ranks=2 seed=1) running"), std::string::npos) << slow.out;
  const auto quick = run(cmd + dir + "/quick");
  ASSERT_EQ(quick.rc, 0) << quick.out;
  EXPECT_EQ(quick.out.find(") running"), std::string::npos) << quick.out;
  EXPECT_EQ(slurp(dir + "/slow/beat.csv"), slurp(dir + "/quick/beat.csv"));
}

// Every shipped manifest passes its runner's checks at each of its profiles as shipped (no overrides but the traces
// folder replay_score is given by the Makefile): a job that `make experiments` or a paper-profile run would refuse
// (a missing file, a rank count that does not fit a workload) fails here. And --check itself refuses such a job.
TEST(Sweep, ShippedManifestsPassTheirChecksAtEveryProfile) {
  for (const auto& entry : fs::directory_iterator(source("experiments")))
    if (entry.path().extension() == ".yaml")
      for (const char* profile : {"small", "paper"}) {
        if (slurp(entry.path().string()).find(std::string("  ") + profile + ":") == std::string::npos) continue;
        const std::string sets = entry.path().stem() == "replay_score" ? " --set traces=" + source("results/cpu") : "";
        const auto r = run(semlb_bin() + " sweep " + entry.path().string() + " --profile " + profile + sets +
                           " --check --results " + fresh_dir("check"));
        EXPECT_EQ(r.rc, 0) << entry.path() << " --profile " << profile << ": " << r.out;
        EXPECT_NE(r.out.find("jobs checked"), std::string::npos) << r.out;
      }
  const auto dir = fresh_dir("check_refuses");
  write(dir + "/m.yaml", "name: w\nrunner: workload_eval\noutput: w.csv\naxes:\n  ranks: [2, 200]\n  workload: [" +
                             source("results/cpu/workloads/small_dev_s1.h5") +
                             "]\n  policy: [static]\n  seed: \"0\"\n");
  const auto bad = run(semlb_bin() + " sweep " + dir + "/m.yaml --check --results " + dir + "/out");
  EXPECT_EQ(bad.rc, 2) << bad.out;
  EXPECT_NE(bad.out.find("200 ranks"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(dir + "/out/w.csv.partial"));
}

// The accuracy runner's reference is double at reference_dt and reference_cutoff whichever form the job gives its own
// precision in: with the job in float at the reference's own dt and cutoff, its error is float's, not 0, whether
// precision is the named setting or scene.backend.precision (a GPU script's form).
TEST(Sweep, AccuracyReferenceIsDoubleWhicheverFormSetsTheJobsPrecision) {
  const auto dir = fresh_dir("sweep_reference");
  const std::string head =
      "name: ref\nrunner: engine_accuracy\noutput: ref.csv\nset:\n  scene: " + source("scenes/mechanics.yaml") +
      "\n  effects: mechanics\n  backend: cpu-binned\n  cells: 20\n  hours: 0.1\n  dt: 0.02\n"
      "  reference_dt: 0.02\n  reference_cutoff: 8.75\n";
  for (const std::string form : {"precision", "scene.backend.precision"}) {
    write(dir + "/m.yaml", head + "  " + form + ": float\n");
    const auto r = run(semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --results " + dir + "/" + form);
    ASSERT_EQ(r.rc, 0) << form << ": " << r.out;
    const auto rows = semlb::csv_rows(dir + "/" + form + "/ref.csv");
    ASSERT_EQ(rows.size(), 1u) << form;
    EXPECT_GT(std::stod(rows[0].at("rms_error_um")), 0.0) << form << ": the reference ran in float too";
    EXPECT_LT(std::stod(rows[0].at("rms_error_um")), 1e-3) << form;
    EXPECT_EQ(rows[0].at("precision"), "float") << form;
  }
}
