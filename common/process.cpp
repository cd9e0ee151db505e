// fork + execvpe with a pipe for the child's output (the child in its own process group, ended with its parent),
// waitpid for its status; the process's own age from /proc.
#include "process.hpp"

#include "cleanup.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace semlb {

double process_seconds() {
  static const auto first = std::chrono::steady_clock::now();
  const double fallback = std::chrono::duration<double>(std::chrono::steady_clock::now() - first).count();
  std::ifstream f("/proc/self/stat");
  const std::string stat((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t close = stat.rfind(')');  // the command name may hold spaces and parentheses
  const long ticks = sysconf(_SC_CLK_TCK);
  timespec now{};
  if (close == std::string::npos || ticks <= 0 || clock_gettime(CLOCK_BOOTTIME, &now) != 0) return fallback;
  std::istringstream rest(stat.substr(close + 1));
  std::string field;
  for (int k = 3; k < 22 && rest >> field; ++k) {  // fields 3 (state) to 21
  }
  unsigned long long start = 0;
  if (!(rest >> start)) return fallback;
  const double age = static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec) -
                     static_cast<double>(start) / static_cast<double>(ticks);
  return age >= 0 ? age : fallback;
}

namespace {
double g_main_started = 0;
}
void mark_main_started() { g_main_started = process_seconds(); }
double main_started_seconds() { return g_main_started; }

ProcessResult run_process(const std::vector<std::string>& argv, const std::vector<std::string>& env) {
  if (argv.empty()) throw std::runtime_error("run_process: no program");
  std::vector<std::string> vars = env;  // the given variables, then the inherited ones they do not replace
  for (char** e = environ; *e; ++e) {
    const std::string var = *e, name = var.substr(0, var.find('='));
    bool replaced = false;
    for (const auto& v : env) replaced = replaced || v.substr(0, v.find('=')) == name;
    if (!replaced) vars.push_back(var);
  }
  std::vector<char*> args, envp;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  for (const auto& v : vars) envp.push_back(const_cast<char*>(v.c_str()));
  args.push_back(nullptr);
  envp.push_back(nullptr);

  // The child in a process group of its own (the group is what a signal-time cleanup stops: common/cleanup.hpp),
  // with SIGTERM when this thread ends (PR_SET_PDEATHSIG: even a SIGKILL of semlb ends mpiexec and, through it, its
  // ranks), an empty signal mask, stdout and stderr into the pipe. Pipes close on exec, so a child started by
  // another thread meanwhile holds no end of them; `err` carries exec's errno back.
  int fd[2], err[2];
  if (::pipe2(fd, O_CLOEXEC) != 0)
    throw std::runtime_error("cannot run " + argv[0] + ": pipe: " + std::strerror(errno));
  if (::pipe2(err, O_CLOEXEC) != 0) {
    ::close(fd[0]);
    ::close(fd[1]);
    throw std::runtime_error("cannot run " + argv[0] + ": pipe: " + std::strerror(errno));
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {  // async-signal-safe calls only from here on
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::dup2(fd[1], 1);
    ::dup2(fd[1], 2);
    ::execvpe(args[0], args.data(), envp.data());
    const int e = errno;
    (void)!::write(err[1], &e, sizeof e);
    ::_exit(127);
  }
  const int fork_errno = errno;
  ::close(fd[1]);
  ::close(err[1]);
  if (pid < 0) {
    ::close(fd[0]);
    ::close(err[0]);
    throw std::runtime_error("cannot run " + argv[0] + ": fork: " + std::strerror(fork_errno));
  }
  ::setpgid(pid, pid);  // also here: the group exists before anyone signals it
  register_child_group(pid);
  int exec_errno = 0;
  ssize_t got;
  while ((got = ::read(err[0], &exec_errno, sizeof exec_errno)) < 0 && errno == EINTR) {
  }
  ::close(err[0]);
  if (got == static_cast<ssize_t>(sizeof exec_errno)) {  // exec failed: reap the child, say why
    ::close(fd[0]);
    while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
    }
    unregister_child_group(pid);
    throw std::runtime_error("cannot run " + argv[0] + ": " + std::strerror(exec_errno));
  }
  ProcessResult r;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd[0], buf, sizeof buf)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    r.output.append(buf, static_cast<size_t>(n));
  }
  ::close(fd[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  unregister_child_group(pid);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

std::string shell_words(const std::vector<std::string>& argv) {
  std::string line;
  for (const auto& a : argv) {
    const bool plain =
        !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./:,@%") ==
                          std::string::npos;
    std::string q = "'";
    for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += (line.empty() ? "" : " ") + (plain ? a : q + "'");
  }
  return line;
}

}  // namespace semlb
