// Ranks that share one device take turns for their device work (decomposition.device_sharing: turns), so that each
// rank's device timers measure its kernels as if it had the device alone (docs/measured_time.md).
#pragma once
#include <string>

namespace semlb::engine {

// An exclusive turn on one device among the processes of a node: an advisory lock (flock(2)) on a file that every
// process sharing the device opens by the same path. Holding a turn while blocked in MPI would stall the others, so
// a turn covers device work only (Simulation::in_turn). Turns need no fairness: whoever waits gets the device when it
// is free, and the timers count device execution, not waiting.
class DeviceTurns {
 public:
  // Opens (creating it if needed) the lock file `path`; std::runtime_error naming it when it cannot.
  explicit DeviceTurns(std::string path);
  ~DeviceTurns();
  DeviceTurns(const DeviceTurns&) = delete;
  DeviceTurns& operator=(const DeviceTurns&) = delete;
  void acquire();  // blocks until this process holds the device; std::runtime_error on a lock error
  void release();  // no-op when not held
  bool held() const { return held_; }
  const std::string& path() const { return path_; }
  // The lock file of the device `device_key` (Backend::device_key) for the job named `job` (the same on every rank
  // of one job on a node, different between jobs): /dev/shm when it exists, else the temporary folder.
  static std::string path_for(const std::string& job, const std::string& device_key);

 private:
  std::string path_;
  int fd_ = -1;
  bool held_ = false;
};

}  // namespace semlb::engine
