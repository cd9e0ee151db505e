// DeviceTurns: one holder at a time, also across a holder that leaves (its destructor removes the lock file) while
// another waits and a third opens the path afresh.
#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>

#include "engine/simulation/device_turns.hpp"

namespace semlb::engine {
namespace {

using namespace std::chrono_literals;

std::string fresh_path(const std::string& tag) {
  return DeviceTurns::path_for("test-" + std::to_string(::getpid()) + "-" + tag, "dev#0");
}

// Waits up to `limit` for `flag`; false when it never rose.
bool rises(const std::atomic<bool>& flag, std::chrono::milliseconds limit = 5000ms) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (!flag && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(5ms);
  return flag;
}

TEST(DeviceTurns, OneHolderAtATime) {
  const auto path = fresh_path("one");
  DeviceTurns a(path), b(path);  // two open files of one path: flock(2) excludes them as it does two processes
  a.acquire();
  EXPECT_TRUE(a.held());
  std::atomic<bool> got{false};
  std::thread t([&] {
    b.acquire();
    got = true;
  });
  std::this_thread::sleep_for(200ms);
  EXPECT_FALSE(got) << "a second holder while the first holds its turn";
  a.release();
  EXPECT_TRUE(rises(got)) << "the waiter never got its turn after the release";
  t.join();
  b.release();
}

// The holder leaves (removing the file) while B waits; C, made after, opens a new file at the path. B must find its
// file gone when its turn comes and lock the new one, so that B and C never hold turns at the same time.
TEST(DeviceTurns, ALeaverRemovingTheFileKeepsTheTurnsExclusive) {
  const auto path = fresh_path("leave");
  auto a = std::make_unique<DeviceTurns>(path);
  DeviceTurns b(path);
  a->acquire();
  std::atomic<bool> b_got{false}, b_done{false};
  std::thread tb([&] {
    b.acquire();
    b_got = true;
    while (!b_done) std::this_thread::sleep_for(5ms);
    b.release();
  });
  std::this_thread::sleep_for(100ms);
  a.reset();  // releases and removes the file
  ASSERT_TRUE(rises(b_got)) << "B never got its turn after A left";
  EXPECT_TRUE(std::filesystem::exists(path)) << "B holds its turn on a file that is no longer at the path";
  DeviceTurns c(path);
  std::atomic<bool> c_got{false};
  std::thread tc([&] {
    c.acquire();
    c_got = true;
  });
  std::this_thread::sleep_for(200ms);
  EXPECT_FALSE(c_got) << "C got a turn while B holds one";
  b_done = true;
  EXPECT_TRUE(rises(c_got)) << "C never got its turn after B's release";
  tb.join();
  tc.join();
  c.release();
}

TEST(DeviceTurns, AnUnopenablePathIsAnErrorNamingIt) {
  try {
    DeviceTurns t("/nonexistent-folder-of-semlb/turns");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder-of-semlb/turns"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace semlb::engine
