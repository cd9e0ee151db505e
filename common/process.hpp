// Child processes started from an argument vector (posix_spawnp): no shell between semlb and what it starts.
#pragma once
#include <string>
#include <vector>

namespace semlb {

struct ProcessResult {
  int status = 0;      // the exit code; 128 + N when killed by signal N
  std::string output;  // stdout and stderr together
};

// Runs argv[0] (looked up in PATH) with argv, the environment plus `env` ("NAME=VALUE", replacing a variable
// of the same name), and waits for it; its stdout and stderr are collected. Throws std::runtime_error naming
// the program when it cannot be started. Nothing in argv is interpreted by a shell. The child runs in a process
// group of its own, registered while it runs (common/cleanup.hpp: a SignalCleanup stops it), and gets SIGTERM if
// the calling thread ends first (a SIGKILL of semlb included).
ProcessResult run_process(const std::vector<std::string>& argv, const std::vector<std::string>& env = {});

// Wall seconds since this process started (the kernel's start time of the process, /proc/self/stat field 22, against
// CLOCK_BOOTTIME; 1/CLK_TCK = 10 ms resolution), so the dynamic loader and static initialisation count; where /proc
// cannot say, the seconds since the first call.
double process_seconds();

// Marks main()'s start (its first statement calls it): main_started_seconds() then gives process_seconds() at that
// moment, the part of a run's start spent loading the program (dynamic libraries, static setup); 0 when never marked.
void mark_main_started();
double main_started_seconds();

// argv as one line for messages, each word quoted for /bin/sh where it needs it (copy-paste reproduces it).
std::string shell_words(const std::vector<std::string>& argv);

}  // namespace semlb
