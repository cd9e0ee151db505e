// Signal-time cleanup: a thread that waits for SIGINT/SIGTERM/SIGHUP, stops the registered child groups, removes the
// registered paths and ends the process by the signal; stale run folders of dead processes.
#include "cleanup.hpp"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <mutex>
#include <set>
#include <vector>

namespace semlb {
namespace {

struct Registry {
  std::mutex mu;
  std::set<pid_t> groups;
  std::multiset<std::string> paths;
};
Registry& registry() {
  static Registry r;
  return r;
}

sigset_t handled() {
  sigset_t s;
  sigemptyset(&s);
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGUSR2}) sigaddset(&s, sig);  // SIGUSR2: the destructor's wake-up
  return s;
}

std::set<pid_t> live_groups() {
  std::lock_guard lock(registry().mu);
  return registry().groups;
}

// Stops the children, removes the paths, and ends the process by `sig`.
[[noreturn]] void clean_up_and_die(int sig, double grace_s) {
  for (pid_t g : live_groups()) ::kill(-g, SIGTERM);
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_s);
  while (!live_groups().empty() && std::chrono::steady_clock::now() < until) ::usleep(20000);
  for (pid_t g : live_groups()) ::kill(-g, SIGKILL);
  std::vector<std::string> paths;
  {
    std::lock_guard lock(registry().mu);
    paths.assign(registry().paths.begin(), registry().paths.end());
  }
  for (const auto& p : paths) {
    std::error_code ec;
    std::filesystem::remove_all(p, ec);  // best effort: the process is ending
  }
  ::signal(sig, SIG_DFL);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, sig);
  ::pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  ::raise(sig);
  ::_exit(128 + sig);  // not reached: the default action of sig ends the process
}

bool g_stopping = false;  // set by ~SignalCleanup before it wakes the waiter

}  // namespace

void register_cleanup_path(const std::string& path) {
  std::lock_guard lock(registry().mu);
  registry().paths.insert(path);
}

void unregister_cleanup_path(const std::string& path) {
  std::lock_guard lock(registry().mu);
  if (auto it = registry().paths.find(path); it != registry().paths.end()) registry().paths.erase(it);
}

void register_child_group(pid_t group) {
  std::lock_guard lock(registry().mu);
  registry().groups.insert(group);
}

void unregister_child_group(pid_t group) {
  std::lock_guard lock(registry().mu);
  registry().groups.erase(group);
}

SignalCleanup::SignalCleanup(double grace_s) : grace_s_(grace_s) {
  const sigset_t set = handled();
  ::pthread_sigmask(SIG_BLOCK, &set, nullptr);
  g_stopping = false;
  waiter_ = std::thread([this] {
    const sigset_t set = handled();
    for (;;) {
      int sig = 0;
      if (::sigwait(&set, &sig) != 0) continue;
      if (sig == SIGUSR2) {
        if (__atomic_load_n(&g_stopping, __ATOMIC_ACQUIRE)) return;
        continue;
      }
      clean_up_and_die(sig, grace_s_);
    }
  });
}

SignalCleanup::~SignalCleanup() {
  __atomic_store_n(&g_stopping, true, __ATOMIC_RELEASE);
  ::pthread_kill(waiter_.native_handle(), SIGUSR2);
  waiter_.join();
  sigset_t set = handled();
  sigdelset(&set, SIGUSR2);
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);  // a signal that came meanwhile now acts as usual
}

int remove_stale_run_folders(const std::string& dir, const std::string& prefix) {
  int removed = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const size_t end = name.find('_', prefix.size());
    const std::string digits =
        name.substr(prefix.size(), end == std::string::npos ? std::string::npos : end - prefix.size());
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    if (pid <= 0 || pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH)
      continue;  // alive, or not ours to judge
    std::error_code rm;
    std::filesystem::remove_all(entry.path(), rm);
    removed += !rm;
  }
  return removed;
}

}  // namespace semlb
