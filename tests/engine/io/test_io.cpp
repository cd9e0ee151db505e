// State files, scene errors, and the run driver: outputs, bit-for-bit restart, nothing written on bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "../../run_command.hpp"
#include "common/h5.hpp"
#include "engine/run/driver.hpp"
#include "engine/effects/effect.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "common/text_io.hpp"
#include "../engine_fixtures.hpp"

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

// The balancer part of a decomposed run's checkpoint: written and read back exactly; every field checked on
// reading (a corrupt dataset is bad input naming the file and dataset, never an internal error).
// A file with a cell field no effect declares (effects/cell_fields.hpp) is refused when read, not carried unread.
TEST(Io, UnknownCellFieldsAreRefused) {
  const auto dir = fresh_dir("io_unknown_field");
  State s = testing::random_state(3, 4, 10.0, 1);
  s.cell_fields["growth.clock"] = {0.1, 0.2, 0.3};
  write_state(dir + "/ok.h5", s, {});
  EXPECT_EQ(read_state(dir + "/ok.h5").cell_fields.count("growth.clock"), 1u);
  s.cell_fields["polarity.angle"] = {1, 2, 3};
  write_state(dir + "/bad.h5", s, {});
  try {
    read_state(dir + "/bad.h5");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.h5: dataset /cells/fields/polarity.angle: unknown cell field"),
              std::string::npos)
        << e.what();
  }
}

TEST(Io, DecompositionCheckpointRoundTripsAndIsChecked) {
  const auto dir = fresh_dir("io_decomposition");
  const State s = testing::random_state(6, 4, 20.0, 3);
  DecompositionCheckpoint d{
      "",   3,     40,
      4,    "gru", 6,
      -1.5, 38.25, BalancerState{7, 12, {10, 25}, {{"hidden", {0.5, -0.25}}, {"tracker.prev_imbalance", {0.1, 0.2}}}}};
  write_state(dir + "/ok.h5", s, {}, &d);
  const auto back = read_decomposition(dir + "/ok.h5");
  ASSERT_TRUE(back);
  EXPECT_EQ(back->file, dir + "/ok.h5");
  EXPECT_EQ(std::tie(back->ranks, back->slices, back->min_width, back->policy, back->cells_at_event),
            std::tie(d.ranks, d.slices, d.min_width, d.policy, d.cells_at_event));
  EXPECT_EQ(std::pair(back->x_lo, back->x_hi), std::pair(d.x_lo, d.x_hi));
  EXPECT_EQ(back->balancer.event, 7);
  EXPECT_EQ(back->balancer.migration, 12);
  EXPECT_EQ(back->balancer.boundaries, d.balancer.boundaries);
  EXPECT_EQ(back->balancer.policy, d.balancer.policy);
  write_state(dir + "/plain.h5", s, {});
  EXPECT_FALSE(read_decomposition(dir + "/plain.h5"));  // a one-device checkpoint has no balancer

  // Each corruption rewrites one dataset of a copy.
  const std::vector<std::tuple<std::string, std::vector<int64_t>, std::string>> ints{
      {"/decomposition/migration", {}, "/decomposition/migration"},
      {"/decomposition/migration", {1, 2}, "/decomposition/migration"},
      {"/decomposition/migration", {-1}, "/decomposition/migration"},
      {"/decomposition/counters", {1, 3, 7, 6, 40}, "/decomposition/counters"},
      {"/decomposition/counters", {2, 3, 7, 6, 40, 4}, "format version 2"},
      {"/decomposition/counters", {1, (1L << 32) + 3, 7, 6, 40, 4}, "ranks = 4294967299"},
      {"/decomposition/counters", {1, 3, (1L << 31) - 1, 6, 40, 4}, "event = 2147483647"},
      {"/decomposition/counters", {1, 3, 7, 6, 40, 41}, "min_width = 41"},
      {"/decomposition/boundaries", {10}, "/decomposition/boundaries"},
  };
  for (const auto& [dataset, values, expected] : ints) {
    fs::copy_file(dir + "/ok.h5", dir + "/bad.h5", fs::copy_options::overwrite_existing);
    {
      auto f = h5::File::open_write(dir + "/bad.h5");
      H5Ldelete(f.id(), dataset.c_str(), H5P_DEFAULT);
      f.write(dataset, {values.size()}, values);
    }
    try {
      read_decomposition(dir + "/bad.h5");
      ADD_FAILURE() << dataset << " accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(dir + "/bad.h5: ", 0), 0u) << m;
      EXPECT_NE(m.find(expected), std::string::npos) << m;
    }
  }
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

// The handed case (tests/data/duplicate_ids: two cells with id 5): refused at load with exit 2, naming the
// file and the dataset, before any output exists.
TEST(Io, DuplicateCellIdsAreRefused) {
  try {
    read_state(test::source("tests/data/duplicate_ids/dupid.h5"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dupid.h5: dataset /cells/id: id 5 appears twice"), std::string::npos)
        << e.what();
  }
  const auto dir = fresh_dir("io_dupid");
  const auto r = test::run(test::semlb_bin() + " sim --quiet --scene " +
                           test::source("tests/data/duplicate_ids/scene.yaml") + " --out " + dir + "/o");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("dupid.h5: dataset /cells/id: id 5 appears twice"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/o")) << r.out;
}

// Every invariant of a state file, one broken at a time; each is refused naming the file and the dataset.
TEST(Io, StateFileInvariants) {
  const auto dir = fresh_dir("io_invariants");
  const State good = testing::random_state(3, 4, 10.0, 1);  // ids 3, 10, 17
  struct Case {
    const char* name;
    std::function<void(h5::File&)> write;
    const char* message;
  };
  const auto base = [&](h5::File& f, std::vector<int64_t> ids, bool elements = true) {
    f.write("/elements/position", {12, 3}, good.position);
    f.write("/cells/id", {3}, ids);
    f.write("/cells/type", {3}, std::vector<int64_t>{0, 1, 2});
    f.write("/cells/count", {3}, std::vector<int64_t>{4, 4, 4});
    if (elements) {
      std::vector<int64_t> cell, type;
      for (int c = 0; c < 3; ++c)
        for (int e = 0; e < 4; ++e) cell.push_back(ids[c]), type.push_back(c);
      f.write("/elements/cell", {12}, cell);
      f.write("/elements/type", {12}, type);
    }
  };
  const int64_t daughter_bit = int64_t{1} << kRootIdBits;
  const std::vector<Case> cases = {
      {"dup",
       [&](h5::File& f) {
         base(f, {3, 10, 3});
       },
       "dataset /cells/id: id 3 appears twice (cells 0 and 2)"},
      {"negative",
       [&](h5::File& f) {
         base(f, {3, -1, 17});
       },
       "dataset /cells/id: id -1 at 1 is negative"},
      {"high_bits",
       [&](h5::File& f) {
         base(f, {3, 10, 17 | daughter_bit});
       },
       "dataset /cells/id: id 1048593 at 2 has bits at or above 20"},
      {"future_daughter",  // cell 3 at depth 0 will give its first daughter id 3 | 2^20, which cell 2 already holds
       [&](h5::File& f) {
         base(f, {3, 10, 3 | daughter_bit});
         f.write("/cells/fields/division.depth", {3}, std::vector<double>{0, 0, 1});
       },
       "dataset /cells/id: id 1048579 at 2 is one that cell 3 (depth 0) will give a daughter"},
      {"depth_range",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write("/cells/fields/division.depth", {3}, std::vector<double>{0, 1.5, 0});
       },
       "dataset /cells/fields/division.depth: value at 1 is not an integer in [0, 36]"},
      {"field_nan",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write("/cells/fields/growth.clock", {3}, std::vector<double>{0, NAN, 0});
       },
       "dataset /cells/fields/growth.clock: value at 1 is not finite"},
      {"field_length",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write("/cells/fields/growth.clock", {2}, std::vector<double>{0, 0});
       },
       "dataset /cells/fields/growth.clock must hold one value per cell (3)"},
      {"type_length",
       [&](h5::File& f) {
         f.write("/elements/position", {12, 3}, good.position);
         f.write("/cells/id", {3}, std::vector<int64_t>{3, 10, 17});
         f.write("/cells/type", {2}, std::vector<int64_t>{0, 1});
         f.write("/cells/count", {3}, std::vector<int64_t>{4, 4, 4});
       },
       "dataset /cells/type must hold one value per cell (3)"},
      {"element_cell",
       [&](h5::File& f) {
         base(f, {3, 10, 17}, false);
         std::vector<int64_t> cell(12, 3);
         f.write("/elements/cell", {12}, cell);
       },
       "dataset /elements/cell: element 4 holds 3 but /cells/count places it in cell 10"},
      {"element_type",
       [&](h5::File& f) {
         base(f, {3, 10, 17}, false);
         f.write("/elements/type", {12}, std::vector<int64_t>(12, 0));
       },
       "dataset /elements/type: element 4 holds 0"},
      {"element_slot",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write("/elements/slot", {12}, std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
       },
       "dataset /elements/slot: element 4 holds 4 but /cells/count places it in cell 10 (type 1, slot 0): expected 0"},
      {"element_vertex",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write("/elements/vertex", {12}, std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 10});
       },
       "dataset /elements/vertex: element 10 holds 11 but /cells/count places it in cell 17 (type 2, slot 2): expected 10"},
      {"vertex_length",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write("/elements/vertex", {11}, std::vector<int64_t>(11, 0));
       },
       "dataset /elements/vertex must hold one value per element (12)"},
      {"position_nan",
       [&](h5::File& f) {
         auto p = good.position;
         p[7] = INFINITY;
         f.write("/elements/position", {12, 3}, p);
         f.write("/cells/id", {3}, std::vector<int64_t>{3, 10, 17});
         f.write("/cells/type", {3}, std::vector<int64_t>{0, 1, 2});
         f.write("/cells/count", {3}, std::vector<int64_t>{4, 4, 4});
       },
       "dataset /elements/position: element 2 has a non-finite coordinate"},
      {"step",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write_attr("step", -5L);
       },
       "attribute 'step' is -5, must be >= 0"},
      {"time_nan",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write_attr("time", double(NAN));
       },
       "attribute 'time' is not finite"},
      {"time_neg",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write_attr("time", -1.0);
       },
       "attribute 'time' is -1 h, must be >= 0"},
      {"step_real",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write_attr("step", 2.5);
       },
       "attribute 'step' must be one integer value"},
      {"format",
       [&](h5::File& f) {
         base(f, {3, 10, 17});
         f.write_attr("format", std::string("other"));
       },
       "attribute 'format' is 'other'"},
  };
  for (const auto& c : cases) {
    const std::string path = dir + "/" + c.name + ".h5";
    {
      auto f = h5::File::create(path);
      c.write(f);
    }
    try {
      read_state(path);
      ADD_FAILURE() << c.name << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(c.name) + ".h5: " + c.message), std::string::npos)
          << c.name << ": " << e.what();
    }
  }
  {  // what the division scheme itself produces is accepted: 3 divided once (depth 1) and its daughter
    auto f = h5::File::create(dir + "/divided.h5");
    base(f, {3, 10, 3 | daughter_bit});
    f.write("/cells/fields/division.depth", {3}, std::vector<double>{1, 0, 1});
  }
  EXPECT_EQ(read_state(dir + "/divided.h5").cells(), 3);
}

// The handed case tests/data/mm_domain.yaml (hi: [0.15mm, 80, 60]) and its kin: every number in a scene is
// the whole token, finite and in range; integers are written as integers.
TEST(Io, SceneNumbersAreStrict) {
  const auto error_of = [](const std::string& yaml, const std::vector<std::string>& set = {}) -> std::string {
    try {
      parse_scene(yaml, "s.yaml", set);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  try {
    load_scene(test::source("tests/data/mm_domain.yaml"), {});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mm_domain.yaml:5: field 'domain.hi': '0.15mm' is not a number"),
              std::string::npos)
        << e.what();
  }
  const std::string domain = "name: x\ndomain: {lo: [0, 0, 0], hi: [";
  EXPECT_EQ(error_of(domain + "100um, 80, 60]}\n"), "s.yaml:2: field 'domain.hi': '100um' is not a number");
  EXPECT_EQ(error_of(domain + "inf, 80, 60]}\n"),
            "s.yaml:2: field 'domain.hi': 'inf' is not a finite number in the range of a double");
  EXPECT_EQ(error_of(domain + "1e400, 80, 60]}\n"),
            "s.yaml:2: field 'domain.hi': '1e400' is not a finite number in the range of a double");
  EXPECT_EQ(error_of(domain + "100, 80, 60]}\n"), "");
  EXPECT_EQ(error_of("name: x\ntime: {steps: 2.0}\n"),
            "s.yaml:2: field 'time.steps': '2.0' is not an integer (write integers without '.' or exponent)");
  EXPECT_EQ(error_of("name: x\ntime: {steps: 1e3}\n"),
            "s.yaml:2: field 'time.steps': '1e3' is not an integer (write integers without '.' or exponent)");
  EXPECT_EQ(error_of("name: x\ntime: {steps: 2.5}\n"),
            "s.yaml:2: field 'time.steps': '2.5' is not an integer (write integers without '.' or exponent)");
  EXPECT_EQ(error_of("name: x\nseed: 0x10\n"), "s.yaml:2: field 'seed': '0x10' is not an integer");
  EXPECT_EQ(error_of("name: x\ncutoff: .nan\n"), "s.yaml:2: field 'cutoff': '.nan' is not a number");
  EXPECT_EQ(error_of("name: x\ncutoff: 8.75um\n"), "s.yaml:2: field 'cutoff': '8.75um' is not a number");
  EXPECT_EQ(error_of("name: x\n", {"time.dt=0.01h"}), "--set time.dt: '0.01h' is not a number");
  EXPECT_EQ(error_of("name: x\ntime: {steps: 9223372036854775808}\n"),
            "s.yaml:2: field 'time.steps': '9223372036854775808' does not fit a 64-bit integer");
}

// A key inside a map given by --set is blamed on that --set, not on line 1 of the scene file.
TEST(Io, NestedSetErrorsNameTheSet) {
  auto scene = parse_scene("name: x\neffects:\n  mechanics: {}\n", "s.yaml", {"effects.noise={diffusoin: 0.1}"});
  try {
    make_effects(scene);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--set effects.noise: field 'effects.noise.diffusoin': unknown setting");
  }
}

// Times in run.csv and snapshots.xmf round-trip: snapshots 0.01 h apart near 12345 h stay distinct.
TEST(Io, OutputTimesRoundTrip) {
  const auto dir = fresh_dir("io_times");
  State s = testing::random_state(2, 4, 10.0, 3);
  s.step = 1234500;  // time = step * dt: 12345 h
  write_state(dir + "/start.h5", s, {});
  write_file_atomically(dir + "/scene.yaml",
                        "name: t\ntissue: {file: start.h5}\ntime: {dt: 0.01, steps: 1234503}\n"
                        "output: {log_every: 1, snapshot_every: 1}\nbackend: {name: serial}\n"
                        "effects:\n  mechanics: {}\n");
  auto scene = load_scene(dir + "/scene.yaml", {});
  run_scene(scene, {dir + "/out", "", true, "test", ""});
  std::vector<double> csv_times, xmf_times;
  const auto lines = split(read_file(dir + "/out/run.csv"), '\n');
  ASSERT_EQ(split(lines[0], ',')[1], "time_h");
  for (size_t i = 1; i < lines.size(); ++i)
    if (!lines[i].empty()) csv_times.push_back(parse_real(split(lines[i], ',')[1], ""));
  const std::string xmf = read_file(dir + "/out/snapshots.xmf");
  for (size_t at = 0; (at = xmf.find("<Time Value=\"", at)) != std::string::npos;) {
    at += 13;
    xmf_times.push_back(parse_real(xmf.substr(at, xmf.find('"', at) - at), ""));
  }
  ASSERT_EQ(csv_times.size(), 3u);
  ASSERT_EQ(xmf_times.size(), 4u);  // the first state's snapshot (step 1234500), then one per logged step
  EXPECT_EQ(xmf_times[0], read_state(dir + "/out/snapshots/step_001234500.h5").time);
  EXPECT_EQ(std::vector<double>(xmf_times.begin() + 1, xmf_times.end()), csv_times);
  for (size_t i = 0; i < csv_times.size(); ++i) {
    const State snap = read_state(dir + "/out/snapshots/step_00123450" + std::to_string(i + 1) + ".h5");
    EXPECT_EQ(csv_times[i], snap.time);  // bit for bit
    EXPECT_EQ(csv_times[i], static_cast<double>(1234501 + i) * 0.01);
  }
  EXPECT_LT(csv_times[0], csv_times[1]);
  EXPECT_LT(csv_times[1], csv_times[2]);
}

TEST(Io, RestartFromACheckpointContinuesBitForBit) {
  const std::string scene_file = std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml";
  const std::vector<std::string> small = {"tissue.cells=20", "output.checkpoint_every=100",
                                          "output.snapshot_every=100"};
  auto straight_scene = load_scene(scene_file, [&] {
    auto o = small;
    o.push_back("time.steps=200");
    return o;
  }());
  const auto a = fresh_dir("io_straight"), b = fresh_dir("io_restart");
  run_scene(straight_scene, {a, "", true, "test", ""});
  auto first_half = load_scene(scene_file, [&] {
    auto o = small;
    o.push_back("time.steps=100");
    return o;
  }());
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
  auto second_half = load_scene(scene_file, [&] {
    auto o = small;
    o.push_back("time.steps=200");
    return o;
  }());
  const RunSummary second = run_scene(second_half, {b, b + "/checkpoint.h5", true, "test", ""});
  EXPECT_EQ(second.steps, 100);  // it simulated steps 100..200 only
  EXPECT_EQ(read_state(a + "/final.h5").hash(), read_state(b + "/final.h5").hash());
  EXPECT_EQ(read_state(b + "/final.h5").step, 200);
  const auto straight = split(read_file(a + "/run.csv"), '\n'), restarted = split(read_file(b + "/run.csv"), '\n');
  ASSERT_EQ(restarted.size(), straight.size());
  EXPECT_EQ(restarted[1], marked);                // the first half's row, kept as it was
  for (size_t i = 1; i < straight.size(); ++i) {  // the same steps, times, cells and elements
    const auto want = split(straight[i], ','), got = split(restarted[i], ',');
    EXPECT_EQ(std::vector<std::string>(got.begin(), got.begin() + std::min<size_t>(4, got.size())),
              std::vector<std::string>(want.begin(), want.begin() + std::min<size_t>(4, want.size())))
        << i;
  }
  // Snapshots of steps 0 (the first run's first state), 100 (once: the restart's first state is already
  // there) and 200, as in the straight run.
  const std::string xmf = read_file(b + "/snapshots.xmf");
  auto count = [&](const std::string& text) {
    size_t k = 0;
    for (size_t at = 0; (at = xmf.find(text, at)) != std::string::npos; ++at) ++k;
    return k;
  };
  for (const char* step : {"000000000", "000000100", "000000200"})
    EXPECT_EQ(count(std::string("snapshots/step_") + step + ".h5:/elements/position"), 1u) << step << "\n" << xmf;
  EXPECT_EQ(count("<Grid Name=\"step_"), 3u) << xmf;
  EXPECT_EQ(xmf, read_file(a + "/snapshots.xmf"));
}

}  // namespace
}  // namespace semlb::engine
