// DeviceTurns: an flock(2) on a per-job, per-device file.
#include "device_turns.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace semlb::engine {

namespace {
int open_lock(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0) throw std::runtime_error("device turns: cannot open " + path + ": " + std::strerror(errno));
  return fd;
}
}  // namespace

DeviceTurns::DeviceTurns(std::string path) : path_(std::move(path)), fd_(open_lock(path_)) {}

DeviceTurns::~DeviceTurns() {
  // The file is removed under the lock, so no process holds a turn on it then; one that waited on it finds it gone
  // when its turn comes (acquire) and locks the path's new file with the rest.
  try {
    acquire();
    ::unlink(path_.c_str());
  } catch (...) {
  }
  release();
  if (fd_ >= 0) ::close(fd_);
}

void DeviceTurns::acquire() {
  if (held_) return;
  for (;;) {
    while (::flock(fd_, LOCK_EX) != 0)
      if (errno != EINTR)
        throw std::runtime_error("device turns: lock of " + path_ + " failed: " + std::strerror(errno));
    struct stat locked;
    struct stat now;
    if (::fstat(fd_, &locked) == 0 && ::stat(path_.c_str(), &now) == 0 && locked.st_ino == now.st_ino &&
        locked.st_dev == now.st_dev) {
      held_ = true;
      return;
    }
    // The file was removed (a process that left) while this one waited: its lock guards nothing now.
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
    fd_ = -1;
    fd_ = open_lock(path_);
  }
}

void DeviceTurns::release() {
  if (!held_) return;
  ::flock(fd_, LOCK_UN);
  held_ = false;
}

std::string DeviceTurns::path_for(const std::string& job, const std::string& device_key) {
  std::string name = "semlb-turns-" + job + "-" + device_key;
  for (char& c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
  const std::filesystem::path dir =
      std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
  return (dir / name).string();
}

}  // namespace semlb::engine
