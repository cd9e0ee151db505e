// DirLock: flock(2) on DIR/.semlb.lock, the holder's pid and command written into it.
#include "dir_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cleanup.hpp"
#include "errors.hpp"
#include "process.hpp"

namespace semlb {
namespace {

std::string holder(int fd) {  // the lock file's "PID COMMAND", without its newline
  std::string text;
  char buf[4096];
  for (ssize_t n, at = 0; (n = ::pread(fd, buf, sizeof buf, at)) > 0; at += n) text.append(buf, static_cast<size_t>(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  return text;
}

std::string describe(const std::string& h) {  // "pid N (COMMAND)"
  if (h.empty()) return "an unknown process";
  const size_t sp = h.find(' ');
  return "pid " + h.substr(0, sp) + (sp == std::string::npos ? "" : " (" + h.substr(sp + 1) + ")");
}

std::string this_command() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  std::vector<std::string> argv;
  std::string word;
  for (char c : ss.str())
    if (c == '\0')
      argv.push_back(std::exchange(word, {}));
    else
      word += c;
  return shell_words(argv);
}

}  // namespace

DirLock::DirLock(const std::string& dir, bool wait) : path_((std::filesystem::path(dir) / ".semlb.lock").string()) {
  std::filesystem::create_directories(dir);
  bool said = false;
  for (;;) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw std::runtime_error(path_ + ": cannot create the lock file: " + std::strerror(errno));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      if (err != EWOULDBLOCK) {
        ::close(fd_);
        throw std::runtime_error(path_ + ": cannot lock: " + std::strerror(err));
      }
      const std::string who = describe(holder(fd_));
      if (!wait) {
        ::close(fd_);
        throw InputError(dir + ": in use by " + who + "; wait for it to finish, or pass --wait");
      }
      if (!said) std::fprintf(stderr, "semlb: %s: in use by %s; waiting for it\n", dir.c_str(), who.c_str());
      said = true;
      while (::flock(fd_, LOCK_EX) != 0)
        if (errno != EINTR) {
          ::close(fd_);
          throw std::runtime_error(path_ + ": cannot lock: " + std::strerror(errno));
        }
    }
    // The holder before us removes the file before it unlocks: a lock on a file no longer at path_ is no lock.
    struct stat held {
    }, named{};
    if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino)
      break;
    ::close(fd_);
  }
  // Ours now. A holder that ended cleanly removed the file; one that died left it naming itself.
  if (const std::string stale = holder(fd_); !stale.empty())
    std::fprintf(stderr, "semlb: %s: took over the stale lock of %s, which is no longer running\n", dir.c_str(),
                 describe(stale).c_str());
  const std::string me = std::to_string(::getpid()) + " " + this_command() + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, me.data(), me.size(), 0) != static_cast<ssize_t>(me.size())) {
    const int err = errno;
    ::close(fd_);
    throw std::runtime_error(path_ + ": write failed: " + std::strerror(err ? err : ENOSPC));
  }
  register_cleanup_path(
      path_);  // a SIGINT or SIGTERM (common/cleanup.hpp) removes it too: no stale-lock note next time
}

DirLock::~DirLock() {
  if (fd_ < 0) return;
  unregister_cleanup_path(path_);
  ::unlink(path_.c_str());  // before unlocking: a waiter that then gets the lock sees the file gone and reopens
  ::close(fd_);             // releases the flock
}

}  // namespace semlb
