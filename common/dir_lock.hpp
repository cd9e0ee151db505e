// One writer per output folder: an advisory lock (flock) on DIR/.semlb.lock that names its holder.
#pragma once
#include <string>

namespace semlb {

// Holds DIR/.semlb.lock (flock, exclusive) for its lifetime; the file holds "PID COMMAND" of the holder while it
// is held and is removed on release. The kernel drops the lock when the holder dies, however it dies; the file
// then is still there naming it, which is how a stale lock is told from a clean release.
class DirLock {
 public:
  // Creates DIR if needed and locks it. When another process holds it: with `wait`, says so once on stderr and
  // waits; else throws InputError "DIR: in use by pid N (COMMAND); ...". A lock left by a holder that died is
  // taken over, with a line on stderr naming it. std::runtime_error when the file cannot be created or written.
  DirLock(const std::string& dir, bool wait);
  ~DirLock();
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;
  // The lock file's path.
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace semlb
