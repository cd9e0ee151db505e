// Workload files: the round trip, every refusal naming the file and field, and the edge ghost-band counts.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "common/errors.hpp"
#include "common/h5.hpp"
#include "controllers/workload.hpp"
#include "../workload_fixtures.hpp"

namespace semlb {
namespace {

std::string tmp_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "semlb_test_workload";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

// Three slices, two events, hand-written.
EngineWorkload small() {
  EngineWorkload w = test::workload_shape(3, 1, 20);
  w.x0_um = -5;
  w.slice_width_um = 10;
  w.ghost_reach_um = 8.8375;
  w.ranks = 2;
  w.scene = "hand";
  w.command = "semlb sim ...";
  w.git_revision = "abc";
  w.device = "cpu";
  WorkloadEvent a;
  a.step = 20;
  a.time_h = 1;
  a.cells = 2;
  a.elements = 7;
  a.growth_phase = 0.25;
  a.growth_event = true;
  a.interval_s = 0.5;
  a.slice_work = {12, 0, 30};
  a.slice_elements = {3, 0, 4};
  a.band_below = {3, 0};
  a.band_above = {0, 4};
  WorkloadEvent b = a;
  b.step = 40;
  b.growth_event = false;
  b.slice_work = {10, 5, 30};
  w.events = {a, b};
  return w;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Workload, RoundTripKeepsEveryField) {
  const auto path = tmp_path("round.h5");
  write_workload(path, small());
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  const auto w = read_workload(path);
  const auto want = small();
  EXPECT_EQ(w.slices, 3);
  EXPECT_EQ(w.x0_um, -5);
  EXPECT_EQ(w.ghost_reach_um, 8.8375);
  EXPECT_EQ(w.scene, "hand");
  EXPECT_EQ(w.ranks, 2);
  ASSERT_EQ(w.events.size(), 2u);
  for (size_t t = 0; t < 2; ++t) {
    EXPECT_EQ(w.events[t].step, want.events[t].step);
    EXPECT_EQ(w.events[t].growth_event, want.events[t].growth_event);
    EXPECT_EQ(w.events[t].slice_work, want.events[t].slice_work);
    EXPECT_EQ(w.events[t].slice_elements, want.events[t].slice_elements);
    EXPECT_EQ(w.events[t].band_below, want.events[t].band_below);
    EXPECT_EQ(w.events[t].band_above, want.events[t].band_above);
    EXPECT_EQ(w.events[t].interval_s, want.events[t].interval_s);
  }
}

// A valid workload spoiled one way, and what writing it must say.
struct Spoiled {
  std::function<void(EngineWorkload&)> spoil;
  std::string message;
};
// Each case of `cases` applied to a copy of `valid`: write_workload refuses it with its message and writes nothing.
void expect_refused(const EngineWorkload& valid, const std::vector<Spoiled>& cases, const std::string& path) {
  for (const auto& c : cases) {
    auto w = valid;
    c.spoil(w);
    std::filesystem::remove(path);
    EXPECT_NE(error_of([&] { write_workload(path, w); }).find(c.message), std::string::npos) << c.message;
    EXPECT_FALSE(std::filesystem::exists(path)) << "nothing written for " << c.message;
  }
}

// small() with measured seconds (version 2): event 0's sum 0.5 s, event 1's 0.75 s, each its interval_s.
EngineWorkload measured() {
  EngineWorkload w = small();
  w.cost_regions = 2;
  w.events[0].slice_seconds = {0.125, 0, 0.375};
  w.events[1].slice_seconds = {0.25, 0.125, 0.375};
  w.events[1].interval_s = 0.75;
  return w;
}

TEST(Workload, MeasuredSecondsRoundTripAsVersionTwo) {
  const auto path = tmp_path("measured.h5");
  write_workload(path, measured());
  EXPECT_EQ(h5::File::open_read(path).read_int_attr("version"), 2);
  const auto w = read_workload(path);
  EXPECT_TRUE(has_measured_cost(w));
  EXPECT_EQ(w.cost_regions, 2);
  for (size_t t = 0; t < 2; ++t) EXPECT_EQ(w.events[t].slice_seconds, measured().events[t].slice_seconds);
  write_workload(path, small());  // without measured seconds: version 1, as before
  EXPECT_EQ(h5::File::open_read(path).read_int_attr("version"), 1);
  EXPECT_FALSE(has_measured_cost(read_workload(path)));
}

// measured() with the parts (version 3): interval_s is 0.5 s and 0.75 s; bit 62 holds the 63rd and later stages.
EngineWorkload with_parts() {
  EngineWorkload w = measured();
  w.events[0].part_seconds = {0.25, 0.0625, 0.125, 0.0625};
  w.events[1].part_seconds = {0.375, 0, 0.0625, 0.3125};
  w.events[0].cell_stage_changes = {1, 0, 3};
  w.events[1].cell_stage_changes = {int64_t{1} << 62 | 5, 2, 0};
  return w;
}

TEST(Workload, PartsAndCellStageChangesRoundTripAsVersionThree) {
  const auto path = tmp_path("parts.h5");
  write_workload(path, with_parts());
  EXPECT_EQ(h5::File::open_read(path).read_int_attr("version"), 3);
  const auto w = read_workload(path);
  EXPECT_TRUE(has_measured_cost(w));
  for (size_t t = 0; t < 2; ++t) {
    EXPECT_EQ(w.events[t].part_seconds, with_parts().events[t].part_seconds);
    EXPECT_EQ(w.events[t].cell_stage_changes, with_parts().events[t].cell_stage_changes) << "bit masks kept exactly";
  }
  const std::vector<Spoiled> cases = {
      {[](EngineWorkload& w) { w.events[1].part_seconds[3] = 0.25; },
       "field 'part_seconds': event 1: sums to 0.6875, but interval_s is 0.75"},
      {[](EngineWorkload& w) { w.events[0].part_seconds[1] = -0.0625, w.events[0].part_seconds[3] = 0.1875; },
       "field 'part_seconds': event 0: -0.0625 is not a finite non-negative number"},
      {[](EngineWorkload& w) { w.events[1].part_seconds.pop_back(); },
       "field 'part_seconds': event 1 has 3 entries, expected 4"},
      {[](EngineWorkload& w) { w.events[1].part_seconds.clear(); },
       "field 'part_seconds': present at some events and not at others"},
      {[](EngineWorkload& w) { w.events[0].cell_stage_changes[1] = -1; },
       "field 'cell_stage_changes': event 0: -1 is negative"},
      {[](EngineWorkload& w) { w.events[0].cell_stage_changes.pop_back(); },
       "field 'cell_stage_changes': event 0 has 2 entries, expected 3"},
      {[](EngineWorkload& w) {
         for (auto& e : w.events) e.slice_seconds.clear();
         w.cost_regions = 0;
       },
       "field 'part_seconds': present without slice_seconds"},
  };
  expect_refused(with_parts(), cases, path);
  auto w2 = measured();
  w2.events[0].cell_stage_changes = {1, 0, 0};
  EXPECT_NE(error_of([&] {
              write_workload(path, w2);
            }).find("field 'cell_stage_changes': event 0: present without part_seconds"),
            std::string::npos);
  write_workload(path, with_parts());
  {
    auto f = h5::File::open_write(path);
    H5Ldelete(f.id(), "events/cell_stage_changes", H5P_DEFAULT);
  }
  EXPECT_NE(error_of([&] { read_workload(path); }).find("field 'cell_stage_changes': missing"), std::string::npos);
}

// with_parts() with the list triggers (version 4): 3 builds in event 0 (slice 0 triggered the first and third, slice
// 2 the second), none in event 1 (the test below also saturates it: 40 builds, bit 30 for the 31st and later).
EngineWorkload with_triggers() {
  EngineWorkload w = with_parts();
  w.events[0].list_builds = 3;
  w.events[0].list_triggers = {5, 0, 2};
  w.events[1].list_builds = 0;
  w.events[1].list_triggers = {0, 0, 0};
  return w;
}

TEST(Workload, ListTriggersRoundTripAsVersionFourAndAreReadStrictly) {
  const auto path = tmp_path("triggers.h5");
  auto saturated = with_triggers();
  saturated.events[1].list_builds = 40;
  saturated.events[1].list_triggers = {int64_t{1} << 30 | 1, 0, 0};
  for (const auto& want : {with_triggers(), saturated}) {
    write_workload(path, want);
    EXPECT_EQ(h5::File::open_read(path).read_int_attr("version"), 4);
    const auto w = read_workload(path);
    for (size_t t = 0; t < 2; ++t) {
      EXPECT_EQ(w.events[t].list_builds, want.events[t].list_builds);
      EXPECT_EQ(w.events[t].list_triggers, want.events[t].list_triggers) << "bit masks kept exactly";
      EXPECT_EQ(w.events[t].cell_stage_changes, want.events[t].cell_stage_changes);
    }
  }
  write_workload(path, with_parts());  // without triggers: version 3, as before
  EXPECT_EQ(h5::File::open_read(path).read_int_attr("version"), 3);
  EXPECT_TRUE(read_workload(path).events[0].list_triggers.empty());
  const std::vector<Spoiled> cases = {
      {[](EngineWorkload& w) { w.events[0].list_triggers[2] = 8; },
       "field 'list_triggers': event 0: 8 marks a build beyond the interval's 3"},
      {[](EngineWorkload& w) { w.events[1].list_triggers[0] = 1; },
       "field 'list_triggers': event 1: 1 marks a build beyond the interval's 0"},
      {[](EngineWorkload& w) { w.events[0].list_triggers[1] = -1; }, "field 'list_triggers': event 0: -1 marks"},
      {[](EngineWorkload& w) { w.events[0].list_triggers.pop_back(); },
       "field 'list_triggers': event 0 has 2 entries, expected 3"},
      {[](EngineWorkload& w) { w.events[1].list_triggers.clear(); },
       "field 'list_triggers': present at some events and not at others"},
      {[](EngineWorkload& w) { w.events[0].list_builds = -1; }, "field 'list_builds': event 0: negative"},
      {[](EngineWorkload& w) {
         for (auto& e : w.events) e.part_seconds.clear(), e.cell_stage_changes.clear();
       },
       "field 'list_triggers': present without part_seconds"},
  };
  expect_refused(with_triggers(), cases, path);
  auto w3 = with_parts();
  w3.events[0].list_builds = 2;
  EXPECT_NE(error_of([&] { write_workload(path, w3); }).find("field 'list_builds': event 0: present without"),
            std::string::npos);
  for (const char* name : {"list_triggers", "list_builds"}) {
    write_workload(path, with_triggers());
    {
      auto f = h5::File::open_write(path);
      H5Ldelete(f.id(), (std::string("events/") + name).c_str(), H5P_DEFAULT);
    }
    EXPECT_NE(error_of([&] { read_workload(path); }).find(std::string("field '") + name + "': missing"),
              std::string::npos)
        << name;
  }
  write_workload(path, with_triggers());
  {
    auto f = h5::File::open_write(path);
    H5Adelete(f.id(), "version");
    f.write_attr("version", 5L);
  }
  EXPECT_NE(error_of([&] { read_workload(path); }).find("field 'version': 5 (this semlb reads versions 1 to 4)"),
            std::string::npos);
}

TEST(Workload, MeasuredSecondsAreReadStrictly) {
  const std::vector<Spoiled> cases = {
      {[](EngineWorkload& w) { w.events[0].slice_seconds[2] = -1e-9; },
       "field 'slice_seconds': event 0: -1e-09 is not a finite non-negative number"},
      {[](EngineWorkload& w) { w.events[1].slice_seconds[0] = std::nan(""); }, "field 'slice_seconds': event 1: nan"},
      {[](EngineWorkload& w) { w.events[1].slice_seconds[0] = INFINITY; }, "field 'slice_seconds': event 1: inf"},
      {[](EngineWorkload& w) { w.events[1].slice_seconds.pop_back(); },
       "field 'slice_seconds': event 1 has 2 entries, expected 3"},
      {[](EngineWorkload& w) { w.events[1].slice_seconds.clear(); },
       "field 'slice_seconds': present at some events and not at others"},
      {[](EngineWorkload& w) { w.cost_regions = 0; },
       "field 'cost_regions': must be >= 1 when the events carry slice_seconds"},
      {[](EngineWorkload& w) { w.events[0].slice_seconds[0] = 0.25; },
       "field 'slice_seconds': event 0: sums to 0.625, but interval_s is 0.5"},
      {[](EngineWorkload& w) { w.cost_regions = 4; }, "field 'cost_regions': must be in [0, slices], got 4"},
  };
  expect_refused(measured(), cases, tmp_path("bad_measured.h5"));
  // A version 2 file whose dataset is missing or of another shape
  const auto path = tmp_path("edit_measured.h5");
  write_workload(path, measured());
  {
    auto f = h5::File::open_write(path);
    H5Ldelete(f.id(), "events/slice_seconds", H5P_DEFAULT);
  }
  EXPECT_NE(
      error_of([&] { read_workload(path); }).find("field 'slice_seconds': missing (dataset /events/slice_seconds)"),
      std::string::npos);
  write_workload(path, measured());
  {
    auto f = h5::File::open_write(path);
    H5Ldelete(f.id(), "events/slice_seconds", H5P_DEFAULT);
    f.write("events/slice_seconds", {2, 2}, std::vector<double>(4, 0.1));
  }
  EXPECT_NE(error_of([&] { read_workload(path); }).find("field 'slice_seconds': must be events x 3 (2 x 3)"),
            std::string::npos);
}

TEST(Workload, InvalidContentIsRefusedNamingTheField) {
  struct Case {
    std::function<void(EngineWorkload&)> spoil;
    std::string message;
  };
  const std::vector<Case> cases = {
      {[](EngineWorkload& w) { w.events[1].step = 20; }, "field 'step': event 1: steps must increase"},
      {[](EngineWorkload& w) { w.events[0].slice_work[1] = 0.5; },
       "field 'slice_work': event 0: 0.5 is not a non-negative integer"},
      {[](EngineWorkload& w) { w.events[0].slice_work[1] = 4611686018427387904.0; },  // 2^62: an integer, too large
       "field 'slice_work': event 0: 4611686018427387904 exceeds 9e15, where counts stop being exact in doubles"},
      {[](EngineWorkload& w) { w.events[0].slice_work[1] = -1; }, "field 'slice_work': event 0"},
      {[](EngineWorkload& w) { w.events[1].band_below.pop_back(); },
       "field 'band_below': event 1 has 1 entries, expected 2"},
      {[](EngineWorkload& w) { w.events[0].elements = 8; },
       "field 'slice_elements': event 0: sums to 7, but elements is 8"},
      {[](EngineWorkload& w) { w.events[0].growth_phase = 1; }, "field 'growth_phase': event 0: outside [0, 1)"},
      {[](EngineWorkload& w) { w.min_width = 4; }, "field 'min_width'"},
      {[](EngineWorkload& w) { w.events.clear(); }, "field 'events': the workload has no events"},
      {[](EngineWorkload& w) {  // elements 0 (slice_elements too) with work left
         w.events[0].elements = 0;
         w.events[0].slice_elements = {0, 0, 0};
       },
       "field 'slice_work': event 0: sums to 42 with 0 elements (each element adds at least 1)"},
      {[](EngineWorkload& w) {
         w.events[1].slice_work = {0, 0, 0};
       },
       "field 'slice_work': event 1: sums to 0 with 7 elements"},
      {[](EngineWorkload& w) { w.events[0].interval_s = w.events[1].interval_s = 0; },
       "field 'interval_s': every event's interval is 0 s"},
  };
  for (const auto& c : cases) {
    auto w = small();
    c.spoil(w);
    const auto path = tmp_path("spoiled.h5");
    std::filesystem::remove(path);
    const auto e = error_of([&] { write_workload(path, w); });
    EXPECT_NE(e.find(path + ": " + c.message), std::string::npos) << e;
    EXPECT_FALSE(std::filesystem::exists(path)) << "nothing written for " << c.message;
  }
}

TEST(Workload, FilesOfAnotherFormatVersionOrShapeAreRefused) {
  const auto path = tmp_path("edit.h5");
  auto rewrite = [&](const std::function<void(h5::File&)>& edit) {
    write_workload(path, small());
    auto f = h5::File::open_write(path);
    edit(f);
  };
  rewrite([](h5::File& f) {
    H5Adelete(f.id(), "version");
    f.write_attr("version", 2L);
  });
  EXPECT_NE(error_of([&] { read_workload(path); }).find(path + ": field 'cost_regions'"), std::string::npos)
      << "version 2 without its measured seconds";
  rewrite([](h5::File& f) {
    H5Adelete(f.id(), "version");
    f.write_attr("version", 5L);
  });
  EXPECT_NE(
      error_of([&] { read_workload(path); }).find(path + ": field 'version': 5 (this semlb reads versions 1 to 4)"),
      std::string::npos);
  rewrite([](h5::File& f) {
    H5Adelete(f.id(), "format");
    f.write_attr("format", std::string("semlb-state"));
  });
  EXPECT_NE(error_of([&] { read_workload(path); }).find("field 'format': is 'semlb-state', expected 'semlb-workload'"),
            std::string::npos);
  {  // a state file or any other HDF5 file: no format attribute
    const auto other = tmp_path("other.h5");
    auto f = h5::File::create(other);
    f.write("x", {1}, std::vector<double>{1.0});
  }
  EXPECT_NE(error_of([&] { read_workload(tmp_path("other.h5")); }).find("field 'format': missing"), std::string::npos);
  rewrite([](h5::File& f) {
    H5Ldelete(f.id(), "events/band_above", H5P_DEFAULT);
    f.write("events/band_above", {2, 3}, std::vector<int64_t>(6, 0));
  });
  EXPECT_NE(error_of([&] { read_workload(path); }).find("field 'band_above': must be events x 2 (2 x 2)"),
            std::string::npos);
  rewrite([](h5::File& f) {
    H5Ldelete(f.id(), "events/slice_work", H5P_DEFAULT);
    f.write("events/slice_work", {2, 3}, std::vector<double>(6, 1.5));
  });
  EXPECT_NE(error_of([&] { read_workload(path); }).find("slice_work"), std::string::npos);
  rewrite([](h5::File& f) { H5Ldelete(f.id(), "events/cells", H5P_DEFAULT); });
  EXPECT_NE(error_of([&] { read_workload(path); }).find("field 'cells': missing (dataset /events/cells)"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_workload(tmp_path("absent.h5")); }).find("absent.h5"), std::string::npos);
}

// Slices of 10 um from x0 = 0, reach 4 um: edges at 10, 20, 30.
TEST(Workload, EdgeBandsCountTheElementsWithinReachOfEachEdge) {
  const std::vector<double> x = {5.9, 6.0, 9.99, 10.0, 13.99, 14.0, 25.0, 29.0, 31.0, -3.0, 100.0};
  std::vector<double> below(3, 0.0), above(3, 0.0);
  add_edge_bands(x, 0.0, 10.0, 4, 4.0, below, above);
  // below edge 10: [6, 10) -> 6.0, 9.99; edge 20: [16, 20) -> none; edge 30: [26, 30) -> 29.0
  EXPECT_EQ(below, (std::vector<double>{2, 0, 1}));
  // above edge 10: [10, 14) -> 10.0, 13.99 (14.0 is not, though (14 - 4) / 10 rounds below 1); edge 20: [20, 24) ->
  // none; edge 30: [30, 34) -> 31.0
  EXPECT_EQ(above, (std::vector<double>{2, 0, 1}));
  // brute force on random positions and a reach of several slices
  std::vector<double> many;
  for (int i = 0; i < 500; ++i) many.push_back(-20 + 0.173 * i);
  std::vector<double> b2(7, 0.0), a2(7, 0.0), wb(7, 0.0), wa(7, 0.0);
  add_edge_bands(many, -10.0, 7.0, 8, 15.0, b2, a2);
  for (int k = 1; k < 8; ++k)
    for (double v : many) {
      const double edge = -10.0 + static_cast<double>(k) * 7.0;
      wb[k - 1] += v >= edge - 15.0 && v < edge;
      wa[k - 1] += v >= edge && v < edge + 15.0;
    }
  EXPECT_EQ(b2, wb);
  EXPECT_EQ(a2, wa);
  // Elements far beyond the edges (an edited state, a cell flung away) cost no loop on their distance.
  std::vector<double> b3(3, 0.0), a3(3, 0.0);
  add_edge_bands({1e15, 1e300, -1e300, 31.0}, 0.0, 10.0, 4, 4.0, b3, a3);
  EXPECT_EQ(b3, (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(a3, (std::vector<double>{0, 0, 1}));
}

}  // namespace
}  // namespace semlb
