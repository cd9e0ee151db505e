// Signal-time cleanup: a SIGTERM removes the registered paths, stops the registered child groups and still ends the
// process by the signal; stale run folders are those of pids no longer running; run_process children get their own
// process group.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "../run_command.hpp"
#include "common/cleanup.hpp"
#include "common/process.hpp"

namespace fs = std::filesystem;
using namespace semlb;

TEST(Cleanup, SigtermRemovesRegisteredPathsStopsChildrenAndEndsByTheSignal) {
  const std::string dir = test::fresh_dir("cleanup_signal");
  fs::create_directories(dir + "/run/sub");
  std::ofstream(dir + "/run/sub/f") << "x";
  const pid_t pid = ::fork();
  if (pid == 0) {  // the child: a process that registers a folder and a sleeping child group, then gets SIGTERM
    {
      const SignalCleanup cleanup(0.5);
      register_cleanup_path(dir + "/run");
      const pid_t sleeper = ::fork();
      if (sleeper == 0) {
        ::setpgid(0, 0);
        ::execlp("sleep", "sleep", "60", static_cast<char*>(nullptr));
        ::_exit(127);
      }
      ::setpgid(sleeper, sleeper);
      register_child_group(sleeper);
      std::ofstream(dir + "/sleeper.pid") << sleeper;
      ::kill(::getpid(), SIGTERM);
      ::sleep(30);  // the cleanup thread ends the process before this returns
    }
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_FALSE(fs::exists(dir + "/run"));
  pid_t sleeper = 0;
  std::ifstream(dir + "/sleeper.pid") >> sleeper;
  ASSERT_GT(sleeper, 0);
  for (int i = 0; i < 100 && ::kill(sleeper, 0) == 0; ++i) ::usleep(20000);  // a zombie of init's until reaped
  std::ifstream stat("/proc/" + std::to_string(sleeper) + "/stat");
  std::string line;
  std::getline(stat, line);
  EXPECT_TRUE(line.empty() || line.find(") Z") != std::string::npos) << line;  // gone, or a zombie: not sleeping on
}

TEST(Cleanup, StaleRunFoldersAreThoseOfProcessesNoLongerRunning) {
  const std::string dir = test::fresh_dir("cleanup_stale");
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  for (const std::string name :
       {"semlb_mpi_" + std::to_string(dead) + "_1", "semlb_mpi_" + std::to_string(::getpid()) + "_2",
        std::string("semlb_mpi_1_3"), std::string("semlb_mpi_x_4"), std::string("other_5")})
    fs::create_directories(dir + "/" + name);
  EXPECT_EQ(remove_stale_run_folders(dir, "semlb_mpi_"), 1);
  EXPECT_FALSE(fs::exists(dir + "/semlb_mpi_" + std::to_string(dead) + "_1"));
  for (const std::string name : {"semlb_mpi_" + std::to_string(::getpid()) + "_2", std::string("semlb_mpi_1_3"),
                                 std::string("semlb_mpi_x_4"), std::string("other_5")})
    EXPECT_TRUE(fs::exists(dir + "/" + name)) << name;
}

TEST(Cleanup, RunProcessStartsItsChildInAProcessGroupOfItsOwn) {
  const ProcessResult r = run_process({"sh", "-c", "echo $$ $(ps -o pgid= -p $$)"});
  ASSERT_EQ(r.status, 0) << r.output;
  std::istringstream in(r.output);
  long pid = 0, group = 0;
  in >> pid >> group;
  EXPECT_GT(pid, 0);
  EXPECT_EQ(pid, group) << r.output;
  EXPECT_NE(group, static_cast<long>(::getpgrp()));
  EXPECT_THROW(run_process({"/no/such/program"}), std::runtime_error);
}
