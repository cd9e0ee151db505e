// Test helper: runs a shell command, capturing exit code and combined output; temp directories.
#pragma once
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace semlb::test {

struct Result {
  int rc;
  std::string out;
  double seconds = 0;  // wall time of the command
};

inline Result run(const std::string& cmd) {
  Result r{0, ""};
  const auto t0 = std::chrono::steady_clock::now();
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// A command prefix that ends what follows after `seconds` (TERM, then KILL 5 s later): a hang becomes exit
// code 124 or 137 and a failing test instead of a stuck suite.
inline std::string within(int seconds) { return "timeout -k 5 " + std::to_string(seconds) + " "; }

inline std::string semlb_bin() { return SEMLB_BINARY; }

// NAME=VALUE in this process's environment while it lives (e.g. SEMLB_OPENCL_BUILD_OPTIONS for a kernel variant of the
// backends built meanwhile); the earlier value, or none, afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const std::string& name, const std::string& value) : name_(name) {
    const char* before = std::getenv(name.c_str());
    had_ = before != nullptr;
    saved_ = had_ ? before : "";
    setenv(name.c_str(), value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_)
      setenv(name_.c_str(), saved_.c_str(), 1);
    else
      unsetenv(name_.c_str());
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_, saved_;
  bool had_ = false;
};
inline std::string source(const std::string& rel) { return std::string(SEMLB_SOURCE_DIR) + "/" + rel; }

// A scratch folder per build tree and per running test, SUITE.TEST/NAME (two checkouts running their suites at once do
// not collide, nor do two tests whose shared helper asks for the same NAME while ctest -j runs them side by side).
inline std::string fresh_dir(const std::string& name) {
  char tree[32];
  std::snprintf(tree, sizeof tree, "%016zx", std::hash<std::string>{}(SEMLB_BINARY));
  auto d = std::filesystem::temp_directory_path() / ("semlb_" + std::string(tree));
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info()) {
    std::string test = std::string(info->test_suite_name()) + "." + info->name();
    std::replace(test.begin(), test.end(), '/', '_');  // parameterized tests: Prefix/Suite.Name/3
    d /= test;
  }
  d /= name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d.string();
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace semlb::test
