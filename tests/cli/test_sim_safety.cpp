// `semlb sim` on a full disk, on an output folder in use, and from a state at or past its end.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "../run_command.hpp"

namespace semlb::test {
namespace {

namespace fs = std::filesystem;

std::string sim(const std::string& out, const std::string& extra) {
  return semlb_bin() + " sim --quiet --scene " + source("scenes/mechanics.yaml") + " --out " + out +
         " --set tissue.cells=30 " + extra;
}

// Failure 5: out of space, the run stops with one line naming the file and exit 1 (no crash at exit), leaves no
// temporary or empty file, and the last checkpoint is whole: a restart from it runs.
TEST(CliSimSafety, FullDiskStopsWithOneLineAndLeavesNoPartialFile) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  const auto dir = fresh_dir("sim_disk_full");
  const std::string mnt = dir + "/mnt";
  fs::create_directories(mnt);
  const auto m = run("mount -t tmpfs -o size=300k tmpfs " + mnt);
  if (m.rc != 0) GTEST_SKIP() << "cannot mount a tmpfs here: " << m.out;
  struct Unmount {
    std::string at;
    ~Unmount() { run("umount " + at); }
  } unmount{mnt};
  const auto r =
      run(within(300) + sim(mnt + "/o", "--steps 200 --set output.snapshot_every=10 --set output.checkpoint_every=50"));
  EXPECT_EQ(r.rc, 1) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_NE(r.out.find(mnt + "/o/"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("No space left on device"), std::string::npos) << r.out;  // the cause, not only the file
  for (const auto& e : fs::recursive_directory_iterator(mnt + "/o"))
    if (e.is_regular_file()) {
      EXPECT_EQ(e.path().extension(), e.path().extension() == ".tmp" ? "" : e.path().extension().string()) << e.path();
      EXPECT_GT(e.file_size(), 0u) << e.path();
    }
  ASSERT_TRUE(fs::exists(mnt + "/o/checkpoint.h5"));
  const auto resumed = run(within(300) + sim(dir + "/resumed", "--steps 60 --restart " + mnt + "/o/checkpoint.h5"));
  EXPECT_EQ(resumed.rc, 0) << resumed.out;
}

// Failure 6: a restart at or past the requested end step is refused (exit 2, both steps named) instead of
// running nothing.
TEST(CliSimSafety, RestartAtOrPastItsEndIsRefused) {
  const auto dir = fresh_dir("sim_nothing_to_run");
  ASSERT_EQ(run(sim(dir + "/a", "--steps 20 --set output.checkpoint_every=20")).rc, 0);
  for (const char* steps : {"20", "10"}) {
    const auto r = run(sim(dir + "/b", std::string("--steps ") + steps + " --restart " + dir + "/a/checkpoint.h5"));
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_NE(r.out.find("step " + std::string(steps)), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("step 20"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_FALSE(fs::exists(dir + "/b"));
  }
  EXPECT_EQ(run(sim(dir + "/b", "--steps 30 --restart " + dir + "/a/checkpoint.h5")).rc, 0);
}

// Failure 2 for `semlb sim`: a second run into an output folder in use exits 2 naming the holder.
TEST(CliSimSafety, SecondRunIntoAFolderInUseIsRefused) {
  const auto dir = fresh_dir("sim_lock");
  // The holder: `exec` keeps the shell's pid, so the test ends it by that pid.
  run("sh -c 'echo $$ > " + dir + "/a.pid; exec " + within(600) + sim(dir + "/o", "--steps 100000000") + "' > " + dir +
      "/a.log 2>&1 &");
  const auto t0 = std::chrono::steady_clock::now();
  while (!fs::exists(dir + "/o/run.csv") && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const auto r = run(sim(dir + "/o", "--steps 10"));
  run("kill $(cat " + dir + "/a.pid)");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("in use by pid"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

// A run on one device ended by SIGINT (Ctrl-C) removes its folder's lock on the way out and still ends by the signal
// (exit 130): the next run into the folder has no stale lock to report.
TEST(CliSimSafety, InterruptedRunLeavesNoLock) {
  const auto dir = fresh_dir("sim_sigint");
  // python resets SIGINT, which a shell ignores in a background job, to its default before it runs semlb
  run("(" + within(600) +
      "/usr/bin/python3 -c 'import os, signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL); "
      "os.execv(sys.argv[1], sys.argv[1:])' " +
      sim(dir + "/o", "--steps 100000000") + " > " + dir + "/a.log 2>&1; echo $? > " + dir +
      "/a.rc) > /dev/null 2>&1 &");
  const auto t0 = std::chrono::steady_clock::now();
  while (!fs::exists(dir + "/o/run.csv") && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const auto holder = run("cat " + dir + "/o/.semlb.lock").out;
  ASSERT_FALSE(holder.empty());
  ASSERT_EQ(run("kill -INT " + holder.substr(0, holder.find(' '))).rc, 0);
  while (!fs::exists(dir + "/a.rc") && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(run("cat " + dir + "/a.rc").out, "130\n") << run("cat " + dir + "/a.log").out;
  EXPECT_FALSE(fs::exists(dir + "/o/.semlb.lock"));
  const auto again = run(sim(dir + "/o", "--steps 10"));
  EXPECT_EQ(again.rc, 0) << again.out;
  EXPECT_EQ(again.out.find("stale lock"), std::string::npos) << again.out;
}

// Failure 4 for a scene: a policy's weights file named relative to the scene resolves beside the scene, whatever
// the working directory.
TEST(CliSimSafety, SceneWeightsResolveBesideTheScene) {
  const auto dir = fresh_dir("sim_weights_beside");
  fs::create_directories(dir + "/sub");
  fs::copy_file(source("controllers/weights/gru_default.h5"), dir + "/sub/w.h5");
  write(dir + "/sub/s.yaml",
        slurp(source("scenes/mechanics.yaml")) + "decomposition: {policy: gru, params: {weights: w.h5}}\n");
  const auto r = run("cd " + dir + " && " + semlb_bin() +
                     " sim --quiet --scene sub/s.yaml --out o --steps 10 --set tissue.cells=20");
  EXPECT_EQ(r.rc, 0) << r.out;
}

}  // namespace
}  // namespace semlb::test
