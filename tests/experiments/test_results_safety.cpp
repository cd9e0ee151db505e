// Sweeps never mix, lose or shell-expand results: rows keyed by their settings digest, one writer per results
// folder, ranks started without a shell, manifest paths relative to the manifest.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "../run_command.hpp"
#include "common/text_io.hpp"

using namespace semlb::test;
namespace fs = std::filesystem;

namespace {
// 30 surrogate jobs, one row each.
std::string surrogate_manifest(int events) {
  return "name: digest\nrunner: surrogate\noutput: sub/d.csv\naxes:\n  policy: [static, reactive, holt]\n  ranks: [2, 4]\n"
         "  seed: \"9000-9004\"\nset:\n  events: " +
         std::to_string(events) + "\n";
}
std::string sh(const std::string& s) {  // one word for /bin/sh
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
size_t data_lines(const std::string& path) {
  auto lines = semlb::split(slurp(path), '\n');
  return lines.size() >= 2 ? lines.size() - 2 : 0;  // less the header and the empty piece after the last newline
}
bool wait_for(const std::function<bool()>& ok, double seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  while (!ok()) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > seconds) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return true;
}
}  // namespace

// Failure 1: an interrupted sweep resumed after its manifest changed (events 20 -> 10), or with another policy
// parameter on the command line (--set reactive.alpha, a setting no column shows), recomputes the rows made with
// the old settings: the CSV is the one a fresh run with the new settings writes.
TEST(ResultsSafety, ResumeRecomputesRowsMadeWithOtherSettings) {
  const auto dir = fresh_dir("results_digest");
  const std::string base = semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --jobs 2 --results ";
  write(dir + "/m.yaml", surrogate_manifest(10));
  ASSERT_EQ(run(base + dir + "/ref10").rc, 0);
  ASSERT_EQ(run(base + dir + "/ref10_alpha --set reactive.alpha=0.2").rc, 0);
  const auto ref10 = slurp(dir + "/ref10/sub/d.csv"), ref10_alpha = slurp(dir + "/ref10_alpha/sub/d.csv");
  ASSERT_NE(ref10, ref10_alpha);  // reactive's rows differ

  write(dir + "/m.yaml", surrogate_manifest(20));
  const auto killed = run("SEMLB_SWEEP_KILL_AFTER=7 " + base + dir + "/cut");
  ASSERT_EQ(killed.rc, 128 + 9) << killed.out;
  ASSERT_GE(data_lines(dir + "/cut/sub/d.csv.partial"), 7u);
  write(dir + "/m.yaml", surrogate_manifest(10));  // the manifest edited between the runs
  auto resumed = run(base + dir + "/cut");
  ASSERT_EQ(resumed.rc, 0) << resumed.out;
  EXPECT_NE(resumed.out.find("made with other settings"), std::string::npos) << resumed.out;
  EXPECT_NE(resumed.out.find("0 resumed"), std::string::npos) << resumed.out;
  EXPECT_EQ(slurp(dir + "/cut/sub/d.csv"), ref10);
  EXPECT_NE(slurp(dir + "/cut/sub/d.manifest.yaml").find("events: 10"), std::string::npos);

  const auto killed2 = run("SEMLB_SWEEP_KILL_AFTER=9 " + base + dir + "/cut2");
  ASSERT_EQ(killed2.rc, 128 + 9) << killed2.out;
  resumed = run(base + dir + "/cut2 --set reactive.alpha=0.2");
  ASSERT_EQ(resumed.rc, 0) << resumed.out;
  EXPECT_EQ(slurp(dir + "/cut2/sub/d.csv"), ref10_alpha);
  // An unchanged rerun of an interrupted sweep still resumes every finished row.
  ASSERT_EQ(run("SEMLB_SWEEP_KILL_AFTER=9 " + base + dir + "/cut3").rc, 128 + 9);
  const size_t finished = data_lines(dir + "/cut3/sub/d.csv.partial");
  resumed = run(base + dir + "/cut3");
  ASSERT_EQ(resumed.rc, 0) << resumed.out;
  EXPECT_NE(resumed.out.find("(30 jobs, " + std::to_string(finished) + " resumed; 30 rows)"), std::string::npos)
      << resumed.out;
  EXPECT_EQ(slurp(dir + "/cut3/sub/d.csv"), ref10);
  // A file a setting names is part of the digest by its contents: weights rewritten in place between the runs.
  fs::copy_file(source("controllers/weights/gru_default.h5"), dir + "/w.h5");
  ASSERT_EQ(run("SEMLB_SWEEP_KILL_AFTER=7 " + base + dir + "/cut4 --set gru.weights=" + dir + "/w.h5").rc, 128 + 9);
  const size_t made = data_lines(dir + "/cut4/sub/d.csv.partial");
  fs::copy_file(source("controllers/weights/gru_migration_penalty_8.h5"), dir + "/w.h5",
                fs::copy_options::overwrite_existing);
  resumed = run(base + dir + "/cut4 --set gru.weights=" + dir + "/w.h5");
  ASSERT_EQ(resumed.rc, 0) << resumed.out;
  EXPECT_NE(
      resumed.out.find("recomputing " + std::to_string(made) + " of the " + std::to_string(made) + " finished jobs"),
      std::string::npos)
      << resumed.out;
}

// Failure 2: a second sweep into a results folder in use exits 2 naming the holder and writes nothing; with
// --wait it runs once the first is done, and its CSV holds its own rows only; a dead holder's lock is taken over.
TEST(ResultsSafety, OneSweepWritesAResultsFolderAtATime) {
  const auto dir = fresh_dir("results_lock");
  write(dir + "/m.yaml", surrogate_manifest(2000));
  const std::string base = semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --jobs 1 --results ";
  ASSERT_EQ(run(base + dir + "/ref --set events=10").rc, 0);
  const auto ref10 = slurp(dir + "/ref/sub/d.csv");

  run("(" + within(600) + base + dir + "/r > " + dir + "/a.log 2>&1; echo $? > " + dir + "/a.rc) > /dev/null 2>&1 &");
  ASSERT_TRUE(wait_for([&] { return fs::exists(dir + "/r/sub/d.csv.partial"); }, 60)) << slurp(dir + "/a.log");
  const auto second = run(base + dir + "/r --set events=10");
  const bool first_running = !fs::exists(dir + "/a.rc");
  ASSERT_TRUE(first_running) << "the first sweep ended too soon for this test";
  EXPECT_EQ(second.rc, 2) << second.out;
  EXPECT_NE(second.out.find("in use by pid"), std::string::npos) << second.out;
  EXPECT_NE(second.out.find("semlb sweep"), std::string::npos) << second.out;  // the holder's command
  EXPECT_EQ(std::count(second.out.begin(), second.out.end(), '\n'), 1) << second.out;

  const auto waited = run(within(600) + base + dir + "/r --set events=10 --wait");
  EXPECT_EQ(waited.rc, 0) << waited.out;
  ASSERT_TRUE(wait_for([&] { return fs::exists(dir + "/a.rc"); }, 600));
  EXPECT_EQ(slurp(dir + "/a.rc"), "0\n") << slurp(dir + "/a.log");
  EXPECT_EQ(slurp(dir + "/r/sub/d.csv"), ref10);  // the second sweep's rows, none of the first's
  EXPECT_NE(slurp(dir + "/r/sub/d.manifest.yaml").find("--set events=10"), std::string::npos);

  // A holder killed with -9 leaves its lock file: the next sweep takes it over and says so.
  write(dir + "/m.yaml", surrogate_manifest(10));
  ASSERT_EQ(run("SEMLB_SWEEP_KILL_AFTER=2 " + base + dir + "/s").rc, 128 + 9);
  const auto taken = run(base + dir + "/s");
  EXPECT_EQ(taken.rc, 0) << taken.out;
  EXPECT_NE(taken.out.find("stale lock"), std::string::npos) << taken.out;
  EXPECT_EQ(slurp(dir + "/s/sub/d.csv"), ref10);
}

// A SIGINT (Ctrl-C) or SIGTERM of a sweep removes its lock file on the way out (common/cleanup.hpp), so the next
// sweep has no stale lock to report; the sweep still ends by the signal (exit 130, 143). The manifest copy's first
// line is a command /bin/sh reruns: no empty --profile, every word quoted where it needs it.
TEST(ResultsSafety, InterruptedSweepLeavesNoLockAndRecordsAQuotedCommand) {
  const auto dir = fresh_dir("results_sigint");
  write(dir + "/m.yaml", surrogate_manifest(2000));
  for (const auto& [sig, rc] : {std::pair{"INT", 130}, std::pair{"TERM", 143}}) {
    const std::string out = dir + "/r" + sig;
    // python resets SIGINT, which a shell ignores in a background job, to its default before it runs the sweep
    run("(" + within(600) +
        "/usr/bin/python3 -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); "
        "os.execv(sys.argv[1], sys.argv[1:])' " +
        semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --jobs 1 --results " + out + " > " + out +
        ".log 2>&1; echo $? > " + out + ".rc) > /dev/null 2>&1 &");
    ASSERT_TRUE(wait_for([&] { return fs::exists(out + "/sub/d.csv.partial"); }, 60)) << slurp(out + ".log");
    const std::string holder = slurp(out + "/sub/.semlb.lock");
    ASSERT_FALSE(holder.empty());
    ASSERT_EQ(run(std::string("kill -") + sig + " " + holder.substr(0, holder.find(' '))).rc, 0);
    ASSERT_TRUE(wait_for([&] { return fs::exists(out + ".rc"); }, 60));
    EXPECT_EQ(slurp(out + ".rc"), std::to_string(rc) + "\n") << sig << ": " << slurp(out + ".log");
    EXPECT_FALSE(fs::exists(out + "/sub/.semlb.lock")) << sig;
    write(dir + "/m x.yaml", surrogate_manifest(10));
    const auto next = run(semlb_bin() + " sweep " + sh(dir + "/m x.yaml") + " --no-timing --quiet --results " + out +
                          " --set events=10");
    EXPECT_EQ(next.rc, 0) << next.out;
    EXPECT_EQ(next.out.find("stale lock"), std::string::npos) << next.out;
    const std::string copy = slurp(out + "/sub/d.manifest.yaml");
    const std::string first = copy.substr(0, copy.find('\n'));
    EXPECT_EQ(first, "# semlb sweep '" + dir + "/m x.yaml' --set events=10") << first;
  }
}

// Failure 3: MPI rows start their ranks without a shell: a scene and a results folder whose paths hold
// spaces, $HOME, quotes, ';' and non-ASCII letters run as given, and nothing in them is executed.
TEST(ResultsSafety, MpiRowsTakePathsWithShellCharacters) {
  const auto dir = fresh_dir("results_argv");
  const std::string odd = dir + "/a b $HOME 'q\" ;touch pwned; \xc3\xbc";
  fs::create_directories(odd);
  fs::copy_file(source("scenes/epidermis.yaml"), odd + "/sc ene $x;touch pwned2.yaml");
  write(odd + "/m.yaml",
        "name: odd\nrunner: mpi_sim\noutput: odd.csv\naxes:\n  ranks: [1, 2]\nset:\n"
        "  scene: \"sc ene $x;touch pwned2.yaml\"\n  cells: 20\n  steps: 10\n  rebalance_every: 5\n");
  const auto r = run("cd " + sh(dir) + " && " + within(300) + semlb_bin() + " sweep " + sh(odd + "/m.yaml") +
                     " --no-timing --quiet --results " + sh(odd + "/res $USER ;x"));
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(data_lines(odd + "/res $USER ;x/odd.csv"), 2u);
  for (const auto& e : fs::recursive_directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().rfind("pwned", 0), std::string::npos) << e.path();
}

// Failure 4: a manifest given by its bare file name, or run from inside experiments/, finds its scene beside it.
TEST(ResultsSafety, ManifestByBareNameResolvesItsSceneBesideIt) {
  const auto dir = fresh_dir("results_bare");
  fs::copy_file(source("scenes/mechanics.yaml"), dir + "/mech.yaml");
  write(dir + "/s.yaml",
        "name: ss\nrunner: mpi_sim\noutput: ss/ss.csv\naxes:\n  ranks: [1]\nset:\n  scene: mech.yaml\n"
        "  cells: 20\n  steps: 10\n  policy: static\n  rebalance_every: 5\n");
  auto r =
      run("cd " + sh(dir) + " && " + within(300) + semlb_bin() + " sweep s.yaml --no-timing --quiet --results res");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(data_lines(dir + "/res/ss/ss.csv"), 1u);
  r = run(
      "cd " + sh(source("experiments")) + " && " + within(300) + semlb_bin() +
      " sweep strong_scaling.yaml --no-timing --quiet --set cells=20 --set ranks=1 --set steps=10 --set rebalance_every=5"
      " --results " +
      sh(dir + "/exp"));
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(data_lines(dir + "/exp/strong_scaling/strong_scaling.csv"), 1u);
}
