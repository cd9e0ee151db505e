// DeviceTurns: an flock(2) on a per-job, per-device file.
#include "device_turns.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace semlb::engine {

DeviceTurns::DeviceTurns(std::string path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (fd_ < 0) throw std::runtime_error("device turns: cannot open " + path_ + ": " + std::strerror(errno));
}

DeviceTurns::~DeviceTurns() {
  release();
  if (fd_ >= 0) ::close(fd_);
  ::unlink(path_.c_str());  // the last process to leave removes it; one still running keeps its open file
}

void DeviceTurns::acquire() {
  if (held_) return;
  while (::flock(fd_, LOCK_EX) != 0)
    if (errno != EINTR) throw std::runtime_error("device turns: lock of " + path_ + " failed: " + std::strerror(errno));
  held_ = true;
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
