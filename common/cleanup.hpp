// What a process stops and removes when SIGINT, SIGTERM or SIGHUP ends it: its children's process groups, its
// temporary folders and lock files.
#pragma once
#include <sys/types.h>

#include <string>
#include <thread>

namespace semlb {

// A path removed (recursively) if a signal ends the process while it is registered; unregister it once it is gone
// or kept. Thread-safe.
void register_cleanup_path(const std::string& path);
void unregister_cleanup_path(const std::string& path);

// A running child's process group (run_process registers each child it starts in a group of its own).
void register_child_group(pid_t group);
void unregister_child_group(pid_t group);

// While alive, SIGINT, SIGTERM and SIGHUP are blocked in the constructing thread and every thread it starts after,
// and one thread waits for them. On one it sends SIGTERM to every registered child group, waits up to
// `grace_s` seconds for them to end (then SIGKILL), removes every registered path, and ends the process by that
// signal (exit status 128 + N, as without it). Construct it before starting other threads; at most one at a time.
class SignalCleanup {
 public:
  explicit SignalCleanup(double grace_s = 10.0);
  ~SignalCleanup();
  SignalCleanup(const SignalCleanup&) = delete;
  SignalCleanup& operator=(const SignalCleanup&) = delete;

 private:
  std::thread waiter_;
  double grace_s_;
};

// Removes DIR/PREFIX<pid>_* folders of processes no longer running (a run killed by SIGKILL, which nothing can
// catch); a folder whose pid is alive is left, whoever holds it. Returns how many it removed.
int remove_stale_run_folders(const std::string& dir, const std::string& prefix);

}  // namespace semlb
