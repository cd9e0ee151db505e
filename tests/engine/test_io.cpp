// State files, scene errors, and the run driver: outputs, bit-for-bit restart, nothing written on bad input.
#include <gtest/gtest.h>

#include <filesystem>

#include "../run_command.hpp"
#include "controllers/h5.hpp"
#include "engine/driver.hpp"
#include "engine/io.hpp"
#include "engine/tissue.hpp"
#include "controllers/text_io.hpp"
#include "engine_fixtures.hpp"

namespace semlb::engine {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;

TEST(Io, StateRoundTripsExactly) {
  State s = testing::random_state(7, 5, 10.0, 1);
  s.step = 42;
  s.time = 0.42;
  s.cell_fields["growth.clock"] = std::vector<double>(7, 0.125);
  const auto dir = fresh_dir("io_roundtrip");
  write_state(dir + "/s.h5", s, {{"git_revision", "x"}});
  const State r = read_state(dir + "/s.h5");
  EXPECT_EQ(r.hash(), s.hash());
  EXPECT_EQ(r.step, 42);
  EXPECT_EQ(r.cell_fields.at("growth.clock"), s.cell_fields.at("growth.clock"));
  EXPECT_FALSE(fs::exists(dir + "/s.h5.tmp"));
}

TEST(Io, BadStateFilesAreRefusedNamingFileAndDataset) {
  const auto dir = fresh_dir("io_bad");
  State s = testing::random_state(3, 4, 10.0, 1);
  {
    auto f = h5::File::create(dir + "/bad.h5");
    f.write("/elements/position", {12, 3}, s.position);
    f.write("/cells/id", {3}, std::vector<int64_t>{0, 1, 2});
    f.write("/cells/type", {3}, std::vector<int64_t>{0, 1, 7});
    f.write("/cells/count", {3}, std::vector<int64_t>{4, 4, 4});
  }
  try {
    read_state(dir + "/bad.h5");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.h5: dataset /cells/type: value 7"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_state(dir + "/missing.h5"), InputError);
}

TEST(Io, SceneErrorsNameFileLineAndField) {
  const char* yaml = "name: x\ntime:\n  dt: -1\n";
  try {
    parse_scene(yaml, "bad.yaml", {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bad.yaml:3: field 'time.dt': ", 0), 0u) << e.what();
  }
  try {
    parse_scene("name: x\ntiem: {}\n", "bad.yaml", {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bad.yaml:2: field 'tiem': unknown setting", 0), 0u) << e.what();
  }
  try {
    parse_scene("name: x\n", "bad.yaml", {"time.steps=abc"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--set time.steps: ", 0), 0u) << e.what();
  }
}

TEST(Io, RestartFromACheckpointContinuesBitForBit) {
  const std::string scene_file = std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml";
  const std::vector<std::string> small = {"tissue.cells=20", "output.checkpoint_every=100", "output.snapshot_every=100"};
  auto straight_scene = load_scene(scene_file, [&] { auto o = small; o.push_back("time.steps=200"); return o; }());
  const auto a = fresh_dir("io_straight"), b = fresh_dir("io_restart");
  run_scene(straight_scene, {a, "", true, "test", ""});
  auto first_half = load_scene(scene_file, [&] { auto o = small; o.push_back("time.steps=100"); return o; }());
  run_scene(first_half, {b, "", true, "test", ""});
  EXPECT_EQ(read_state(b + "/checkpoint.h5").step, 100);
  // Mark the first half's log row (its wall_s): the restart keeps it; a run from step 0 would rewrite it.
  auto rows = split(read_file(b + "/run.csv"), '\n');
  ASSERT_EQ(rows.size(), 3u) << read_file(b + "/run.csv");  // header, step 100, ""
  auto cells = split(rows[1], ',');
  ASSERT_EQ(cells[0], "100");
  cells[4] = "12345";
  std::string marked;
  for (const auto& c : cells) marked += (marked.empty() ? "" : ",") + c;
  write_file_atomically(b + "/run.csv", rows[0] + "\n" + marked + "\n");
  auto second_half = load_scene(scene_file, [&] { auto o = small; o.push_back("time.steps=200"); return o; }());
  const RunSummary second = run_scene(second_half, {b, b + "/checkpoint.h5", true, "test", ""});
  EXPECT_EQ(second.steps, 100);  // it simulated steps 100..200 only
  EXPECT_EQ(read_state(a + "/final.h5").hash(), read_state(b + "/final.h5").hash());
  EXPECT_EQ(read_state(b + "/final.h5").step, 200);
  const auto straight = split(read_file(a + "/run.csv"), '\n'), restarted = split(read_file(b + "/run.csv"), '\n');
  ASSERT_EQ(restarted.size(), straight.size());
  EXPECT_EQ(restarted[1], marked);  // the first half's row, kept as it was
  for (size_t i = 1; i < straight.size(); ++i) {  // the same steps, times, cells and elements
    const auto want = split(straight[i], ','), got = split(restarted[i], ',');
    EXPECT_EQ(std::vector<std::string>(got.begin(), got.begin() + std::min<size_t>(4, got.size())),
              std::vector<std::string>(want.begin(), want.begin() + std::min<size_t>(4, want.size()))) << i;
  }
  const std::string xmf = read_file(b + "/snapshots.xmf");
  EXPECT_NE(xmf.find("snapshots/step_000000100.h5:/elements/position"), std::string::npos);
  EXPECT_NE(xmf.find("snapshots/step_000000200.h5:/elements/position"), std::string::npos);
}

}  // namespace
}  // namespace semlb::engine
