// The decomposed run under mpirun: the same final state on 1, 2 and 4 ranks as on one device, a
// checkpoint on 2 ranks continued on 4, engine traces that `semlb replay` reproduces, and failures.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <map>

#include <nlohmann/json.hpp>

#include "../../run_command.hpp"
#include "common/h5.hpp"
#include "common/text_io.hpp"
#include "engine/model/tissue.hpp"
#include "../engine_fixtures.hpp"
#include "engine/decomposition/distributed.hpp"
#include "engine/effects/effect.hpp"
#include "engine/io/io.hpp"
#include "engine/run/driver.hpp"
#include "controllers/workload.hpp"
#include "engine/backends/opencl.hpp"

namespace semlb::engine {
namespace {

using test::fresh_dir;
using test::run;
using test::semlb_bin;
using test::source;
using test::within;

// 400 cells over ~180 um in x: room for 4 slabs of min_width (3 cutoffs); one thread per rank.
const std::string kArgs =
    " --scene " + source("scenes/epidermis.yaml") +
    " --quiet --set tissue.cells=400 --set backend.cpu-binned.threads=1 --set decomposition.rebalance_every=50";

using testing::mpirun_sim;  // every run bounded: a hang fails the test

// W_s = sum of n_i n_N(i) per slice against a brute-force count, on a compact tissue (dense bin counts)
// and on one whose two halves lie 2e6 um apart (over a million bins).
TEST(Decomposition, SliceWorkloadMatchesBruteForceCompactAndSpread) {
  for (double gap : {0.0, 2e6}) {
    State s = testing::random_state(40, 6, 40.0, 21);
    for (long e = s.elements() / 2; e < s.elements(); ++e) s.position[3 * e] += gap;  // cells 20..39 move by gap
    const double cutoff = 8.75;
    Decomposition d;
    d.slices = 7;
    d.width = (gap + 40.0) / 7;
    const auto [lo, hi] = tissue_box(s, cutoff);
    const Grid g = Grid::cover(lo, hi, cutoff);
    std::vector<double> want(d.slices, 0.0);
    for (long c = 0; c < s.cells(); ++c) {
      const auto ctr = centroid(s, c);
      const auto b = g.bin_of(ctr.data());
      long near = 0;
      for (long e = 0; e < s.elements(); ++e) {
        const auto q = g.bin_of(&s.position[3 * e]);
        near += std::abs(q[0] - b[0]) <= 1 && std::abs(q[1] - b[1]) <= 1 && std::abs(q[2] - b[2]) <= 1;
      }
      want[d.slice_of(ctr[0])] += static_cast<double>(s.cell_count[c]) * static_cast<double>(near);
    }
    EXPECT_EQ(slice_workload(s, d, cutoff), want) << "gap " << gap << ", " << g.bins() << " bins";
  }
}

TEST(Decomposition, SameFinalStateOnOneTwoAndFourRanksAsOnOneDevice) {
  const auto dir = fresh_dir("decomposition_ranks");
  const uint64_t reference = testing::expect_same_state_on_ranks(kArgs + " --steps 200", dir).hash();
  for (int ranks : {1, 2, 4})
    EXPECT_EQ(split(read_file(dir + "/np" + std::to_string(ranks) + "/rank_times.csv"), '\n').size(), 2 + 4u * ranks)
        << "4 events x ranks rows";
  // the blocking exchange (decomposition.overlap: false) moves the same bits
  auto r = run(mpirun_sim(2) + kArgs + " --steps 200 --set decomposition.overlap=false --out " + dir + "/blocking");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(read_state(dir + "/blocking/final.h5").hash(), reference) << "2 ranks, blocking exchange";
}

// Everything a workload file holds per event, for comparisons across runs.
std::string workload_of(const std::string& path) {
  const auto w = read_workload(path);
  std::string out;
  for (const auto& e : w.events) {
    out += std::to_string(e.step) + " " + std::to_string(e.cells) + " " + std::to_string(e.elements) + " " +
           std::to_string(e.growth_event) + " " + format_real(e.growth_phase) + ":";
    for (const auto* v : {&e.slice_work, &e.slice_elements, &e.band_below, &e.band_above})
      for (double x : *v) out += " " + format_real(x);
    out += "\n";
  }
  return out;
}

// W_s counted on one grid over the whole tissue: the workload file of one device equals that of 1, 2 and 4 ranks
// under different partitions (static and reactive, workload-aware and uniform starts), and its last event is the host
// reference slice_workload of the final state.
TEST(Decomposition, WorkloadIsTheSameOnOneDeviceAndOnOneTwoAndFourRanks) {
  const auto dir = fresh_dir("decomposition_workload");
  const std::string args = kArgs + " --steps 150 --set output.workload=true";
  auto r = run(semlb_bin() + " sim" + args + " --out " + dir + "/single");
  ASSERT_EQ(r.rc, 0) << r.out;
  const std::string reference = workload_of(dir + "/single/workload.h5");
  EXPECT_EQ(split(reference, '\n').size(), 4u) << "3 events and the final newline";
  for (const std::string variant : {"np1", "np2", "np4", "np2_reactive_uniform"}) {
    const std::string extra = variant == "np2_reactive_uniform"
                                  ? " --set decomposition.policy=reactive --set decomposition.initial=uniform"
                                  : "";
    r = run(mpirun_sim(variant == "np4"   ? 4
                       : variant == "np1" ? 1
                                          : 2) +
            args + extra + " --out " + dir + "/" + variant);
    ASSERT_EQ(r.rc, 0) << r.out;
    EXPECT_EQ(workload_of(dir + "/" + variant + "/workload.h5"), reference) << variant;
  }
  const auto w = read_workload(dir + "/np4/workload.h5");
  EXPECT_EQ(w.ranks, 4);
  SliceMap map;
  map.slices = w.slices;
  map.x0 = w.x0_um;
  map.width = w.slice_width_um;
  EXPECT_EQ(slice_workload(read_state(dir + "/np4/final.h5"), map, w.cutoff_um), w.events.back().slice_work);
}

// The device path of the ghost exchange (bands selected by OpenCL kernels), against one device.
TEST(Decomposition, OpenClRanksMatchOneOpenClDevice) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  const auto dir = fresh_dir("decomposition_opencl");
  const std::string args = kArgs + " --steps 60 --set backend.name=opencl-binned --set output.workload=true";
  auto r = run(semlb_bin() + " sim" + args + " --out " + dir + "/single");
  ASSERT_EQ(r.rc, 0) << r.out;
  const uint64_t reference = read_state(dir + "/single/final.h5").hash();
  const std::string workload = workload_of(dir + "/single/workload.h5");
  // With backend.skin, opencl-binned's neighbour list takes the local pairs (on each rank its owned elements) and the
  // stencil the ghosts: one device and 2 and 4 ranks with the list give the state of one device without it.
  r = run(semlb_bin() + " sim" + args + " --set backend.opencl-binned.skin=1 --out " + dir + "/single_list");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(read_state(dir + "/single_list/final.h5").hash(), reference) << "one device with the list";
  // 2 ranks overlapped and blocking; 4 ranks: the middle ones select both bands in one pass
  // (np*_newton: the half list, each pair once, its force added to both elements atomically)
  const std::string newton = " --set backend.opencl-binned.newton=true";
  for (const std::string variant :
       {"np2", "np2_blocking", "np4", "np2_skin", "np4_skin", "np1_newton", "np2_newton", "np4_newton"}) {
    const std::string extra = variant == "np2_blocking" ? " --set decomposition.overlap=false"
                              : variant == "np2_skin"   ? " --set backend.opencl-binned.skin=0.3"  // rebuilt often
                              : variant == "np4_skin"   ? " --set backend.opencl-binned.skin=1"
                              : variant == "np2_newton" ? " --set backend.opencl-binned.skin=0.3" + newton
                              : variant.find("newton") != std::string::npos
                                  ? " --set backend.opencl-binned.skin=1" + newton
                                  : "";
    const int ranks = variant[2] - '0';
    const bool half = variant.find("newton") != std::string::npos;  // not --quiet: the breakdown names the half list
    const std::string quiet = " --quiet",
                      run_args =
                          half ? args.substr(0, args.find(quiet)) + args.substr(args.find(quiet) + quiet.size()) : args;
    r = run((ranks == 1 ? within(300) + semlb_bin() + " sim" : mpirun_sim(ranks)) + run_args + extra + " --out " + dir +
            "/" + variant);
    ASSERT_EQ(r.rc, 0) << r.out;
    EXPECT_EQ(r.out.find("(half: newton)") != std::string::npos, half) << variant << "\n" << r.out;
    EXPECT_EQ(read_state(dir + "/" + variant + "/final.h5").hash(), reference) << variant;
    EXPECT_EQ(workload_of(dir + "/" + variant + "/workload.h5"), workload)
        << variant << ": W_s on the device, counts summed over ranks";
  }
}

// The rows of DIR/rank_times.csv by column name.
std::vector<std::map<std::string, std::string>> rank_time_rows(const std::string& dir) {
  return csv_rows(dir + "/" + rank_times::kFile, rank_times::kColumns);
}

// decomposition.timing: device and device_sharing: turns on the OpenCL device the tests have (PoCL): 2 and 4 ranks
// taking turns give the one-device state bit for bit, every rank's device time is positive and is what the policy
// saw (compute_s, the trace's times), and the recorded workload carries measured seconds summing to the device time.
TEST(Decomposition, DeviceTimersAndTurnsKeepTheStateAndFeedTheDecisions) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  const auto dir = fresh_dir("decomposition_device_timing");
  const std::string args =
      kArgs + " --steps 100 --set backend.name=opencl-binned --set decomposition.rebalance_every=20";
  auto r = run(semlb_bin() + " sim" + args + " --out " + dir + "/single");
  ASSERT_EQ(r.rc, 0) << r.out;
  const uint64_t reference = read_state(dir + "/single/final.h5").hash();
  const std::string timed =
      " --set decomposition.timing=device --set decomposition.device_sharing=turns --set output.workload=true";
  for (int ranks : {2, 4}) {
    for (const std::string skin : {"0", "0.5"}) {  // the stencil and the neighbour list (timed over regions alike)
      const std::string out = dir + "/np" + std::to_string(ranks) + "_skin" + skin;
      r = run(mpirun_sim(ranks) + args + timed + " --set backend.opencl-binned.skin=" + skin + " --out " + out);
      ASSERT_EQ(r.rc, 0) << r.out;
      EXPECT_EQ(read_state(out + "/final.h5").hash(), reference) << out;
      const auto rows = rank_time_rows(out);
      ASSERT_EQ(rows.size(), 5u * ranks) << out;
      std::map<long, std::vector<double>> device;  // per event, by rank
      for (const auto& row : rows) {
        const double d = parse_real(row.at("device_s"), "device_s");
        EXPECT_GT(d, 0) << out << " step " << row.at("step") << " rank " << row.at("rank");
        EXPECT_EQ(row.at("compute_s"), row.at("device_s")) << "the policy sees the device times";
        EXPECT_GT(parse_real(row.at("exchange_bytes"), "exchange_bytes"), 0) << "every rank sends a band";
        // the parts: pair forces timed, the list's builds only with a list, the cell stage (every 10 steps)
        const double pair = parse_real(row.at("device_pair_s"), "device_pair_s"),
                     list = parse_real(row.at("device_list_s"), "device_list_s"),
                     cells = parse_real(row.at("device_cells_s"), "device_cells_s");
        EXPECT_GT(pair, 0) << out;
        EXPECT_GT(cells, 0) << out;
        EXPECT_EQ(list > 0, skin != "0") << out << ": list " << list;
        EXPECT_LT(pair + list + cells, d) << out << ": the parts leave integration and the terms";
        device[parse_integer(row.at("step"), "step")].push_back(d);
      }
      const auto trace = split(read_file(out + "/trace.jsonl"), '\n');
      ASSERT_GE(trace.size(), 5u);
      for (size_t e = 0; e < 5; ++e) {
        const auto times = nlohmann::json::parse(trace[e]).at("times").get<std::vector<double>>();
        EXPECT_EQ(times, device.at(20 * static_cast<long>(e + 1))) << out << " event " << e;
      }
      const auto w = read_workload(out + "/workload.h5");
      ASSERT_TRUE(has_measured_cost(w)) << out;
      EXPECT_EQ(w.cost_regions, std::min(32, w.slices));
      for (size_t e = 0; e < w.events.size(); ++e) {
        double sum = 0;
        for (double x : w.events[e].slice_seconds) sum += x;
        EXPECT_NEAR(sum, w.events[e].interval_s, 1e-9 * w.events[e].interval_s) << out << " event " << e;
        double ranks_sum = 0;
        for (double d : device.at(w.events[e].step)) ranks_sum += d;
        EXPECT_NEAR(w.events[e].interval_s, ranks_sum, 1e-9 * ranks_sum) << "interval_s: the ranks' device seconds";
        ASSERT_EQ(w.events[e].part_seconds.size(), 4u) << out;
        EXPECT_GT(w.events[e].part_seconds[0], 0) << "pair forces";
        EXPECT_GT(w.events[e].part_seconds[2], 0) << "cell stage";
        EXPECT_EQ(w.events[e].part_seconds[1] > 0, skin != "0") << "list builds with a list only";
        EXPECT_TRUE(w.events[e].list_triggers.empty()) << "a rank's own list: no one-rank triggers on P ranks";
      }
      // the tissue grows: some slice changed at some cell stage (2 per interval: bits 0-1), none beyond
      int64_t any = 0;
      for (const auto& e : w.events)
        for (int64_t m : e.cell_stage_changes) any |= m;
      EXPECT_NE(any, 0) << out;
      EXPECT_EQ(any & ~int64_t{3}, 0) << out;
    }
  }
}

// A recording on one rank with the neighbour list marks the slices whose elements triggered its builds (version 4):
// every event counts its builds, some build was triggered by displacement in some slice, no bit marks a build beyond
// the event's count (read_workload checks it), and the marks change nothing (the state equals the unrecorded run's).
// Without a list (skin 0) the file stays version 3.
TEST(Decomposition, AOneRankRecordingMarksTheSlicesThatTriggerTheListBuilds) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  const auto dir = fresh_dir("decomposition_list_triggers");
  const std::string args =
      kArgs + " --steps 100 --set backend.name=opencl-binned --set decomposition.rebalance_every=20";
  for (const std::string skin : {"0.2", "0"}) {
    const std::string list = " --set backend.opencl-binned.skin=" + skin;
    auto r = run(semlb_bin() + " sim" + args + list + " --out " + dir + "/plain" + skin);
    ASSERT_EQ(r.rc, 0) << r.out;
    r = run(semlb_bin() + " sim" + args + list +
            " --set decomposition.timing=device --set output.workload=true --out " + dir + "/rec" + skin);
    ASSERT_EQ(r.rc, 0) << r.out;
    EXPECT_EQ(read_state(dir + "/rec" + skin + "/final.h5").hash(),
              read_state(dir + "/plain" + skin + "/final.h5").hash())
        << "skin " << skin;
    const auto path = dir + "/rec" + skin + "/workload.h5";
    EXPECT_EQ(h5::File::open_read(path).read_int_attr("version"), skin == "0" ? 3 : 4) << "skin " << skin;
    const auto w = read_workload(path);
    ASSERT_EQ(w.events.size(), 5u);
    if (skin == "0") continue;
    int64_t any = 0;
    for (const auto& e : w.events) {
      EXPECT_GT(e.list_builds, 0) << "step " << e.step;
      ASSERT_EQ(e.list_triggers.size(), static_cast<size_t>(w.slices));
      int64_t marked = 0;
      for (int k = 0; k < w.slices; ++k) {
        marked |= e.list_triggers[k];
        if (e.list_triggers[k] == 0) continue;
        double near = 0;  // a marked slice held a moving element: the tissue is there (within a slice, at the event)
        for (int j = std::max(0, k - 1); j <= std::min(w.slices - 1, k + 1); ++j) near += e.slice_elements[j];
        EXPECT_GT(near, 0) << "step " << e.step << ": slice " << k << " is marked but empty";
      }
      EXPECT_LE(std::popcount(static_cast<uint64_t>(marked)), e.list_builds) << "step " << e.step;
      any |= marked;
    }
    EXPECT_NE(any, 0) << "no build was triggered by an element's displacement";
  }
}

// Events between cell stages (rebalance every 15 steps, cell stages every 10): a recording's cell-stage bits mark
// only the stages that ran in each interval (10 | 20, 30 | 40: bits 0 | 0-1 | 0), and no event reads a stage that
// did not run.
TEST(Decomposition, CellStageChangesMarkOnlyTheStagesThatRan) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  const auto dir = fresh_dir("decomposition_stage_bits");
  const auto r = run(semlb_bin() + " sim" + kArgs +
                     " --steps 45 --set backend.name=opencl-binned --set decomposition.rebalance_every=15" +
                     " --set decomposition.timing=device --set output.workload=true --out " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto w = read_workload(dir + "/out/workload.h5");
  ASSERT_EQ(w.events.size(), 3u);
  const int64_t allowed[3] = {1, 3, 1};
  int64_t any = 0;
  for (size_t e = 0; e < 3; ++e)
    for (int64_t m : w.events[e].cell_stage_changes) {
      EXPECT_EQ(m & ~allowed[e], 0) << "event " << e;
      any |= m;
    }
  EXPECT_NE(any, 0) << "the tissue grows at some stage";
}

// A rank whose slabs hold no element launches no force work: its device time is near zero (a domain twice as wide
// as the tissue, split uniformly and never rebalanced). Its pair-force, list and cell-stage seconds are exactly 0; what
// is left is the launch overhead of its empty kernels, which PoCL times as CPU wall: under a loaded test machine that
// reached 0.7 ms per step (more than the busy rank's 60 cells), so the bound on its total is 5 ms per step.
TEST(Decomposition, ARankWithoutElementsHasNearZeroDeviceTime) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  const auto dir = fresh_dir("decomposition_device_timing_empty");
  const auto r = run(mpirun_sim(2) + " --scene " + source("scenes/epidermis.yaml") +
                     " --quiet --set tissue.cells=60 --steps 40 --set backend.name=opencl-binned"
                     " --set domain.lo=[-20,-20,-20] --set domain.hi=[400,60,60] --set decomposition.initial=uniform"
                     " --set decomposition.policy=static --set decomposition.rebalance_every=20"
                     " --set decomposition.timing=device --set decomposition.device_sharing=turns --out " +
                     dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  int intervals = 0;
  for (const auto& row : rank_time_rows(dir + "/out")) {
    const auto seconds = [&](const char* column) { return parse_real(row.at(column), column); };
    if (row.at("rank") == "0") {
      EXPECT_GT(seconds("device_s"), 0) << "step " << row.at("step");
      EXPECT_GT(seconds("device_pair_s"), 0) << "step " << row.at("step");
      continue;
    }
    ++intervals;
    for (const char* part : {"device_pair_s", "device_list_s", "device_cells_s"})
      EXPECT_EQ(seconds(part), 0) << part << ", step " << row.at("step");
    EXPECT_LT(seconds("device_s"), 20 * 0.005) << "step " << row.at("step");  // 20 steps per interval
  }
  EXPECT_EQ(intervals, 2);
}

TEST(Decomposition, DeviceTimersAndTurnsAreRefusedWhereTheyCannotWork) {
  const auto dir = fresh_dir("decomposition_device_timing_refused");
  for (const auto& [set, message] : std::vector<std::pair<std::string, std::string>>{
           {"decomposition.timing=device", "decomposition.timing: device timers need an OpenCL backend"},
           {"decomposition.device_sharing=turns", "decomposition.device_sharing: turns share an OpenCL device"},
           {"decomposition.timing=clock", "must be measured, modelled or device"},
           {"decomposition.device_sharing=always", "must be none or turns"}}) {
    const auto r = run(semlb_bin() + " sim" + kArgs + " --steps 1 --set " + set + " --out " + dir + "/out");
    EXPECT_EQ(r.rc, 2) << set << ": " << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out")) << set;
  }
  const auto r = run(semlb_bin() + " sim" + kArgs +
                     " --steps 1 --set backend.name=opencl-binned --set decomposition.device_sharing=turns"
                     " --set decomposition.overlap=true --out " +
                     dir + "/out");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("decomposition.overlap: true cannot be combined with device_sharing: turns"), std::string::npos)
      << r.out;
}

TEST(Decomposition, OverlapIsTrueOrFalse) {
  const auto dir = fresh_dir("decomposition_overlap_flag");
  const auto r = run(semlb_bin() + " sim" + kArgs + " --steps 1 --set decomposition.overlap=yes --out " + dir + "/out");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("--set decomposition.overlap: must be true or false, got 'yes'"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

TEST(Decomposition, CheckpointOnTwoRanksContinuesIdenticallyOnFour) {
  const auto dir = fresh_dir("decomposition_restart");
  auto r = run(mpirun_sim(2) + kArgs + " --steps 200 --out " + dir + "/straight");
  ASSERT_EQ(r.rc, 0) << r.out;
  r = run(mpirun_sim(2) + kArgs + " --steps 100 --set output.checkpoint_every=100 --out " + dir + "/first");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(read_state(dir + "/first/checkpoint.h5").step, 100);
  r = run(mpirun_sim(4) + kArgs + " --steps 200 --restart " + dir + "/first/checkpoint.h5 --out " + dir + "/second");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(read_state(dir + "/second/final.h5").hash(), read_state(dir + "/straight/final.h5").hash());
  // ... and it simulated steps 100..200 only: a run from step 0 would also log step 100 and time 4 intervals.
  EXPECT_NE(r.out.find("semlb sim: 100 steps,"), std::string::npos) << r.out;
  const auto log = split(read_file(dir + "/second/run.csv"), '\n');
  ASSERT_EQ(log.size(), 3u) << read_file(dir + "/second/run.csv");  // header, step 200, ""
  EXPECT_EQ(split(log[1], ',')[0], "200");
  const auto times = split(read_file(dir + "/second/rank_times.csv"), '\n');
  ASSERT_EQ(times.size(), 2 + 2u * 4) << "2 events x 4 ranks rows";
  for (size_t i = 1; i + 1 < times.size(); ++i) EXPECT_GT(std::stol(split(times[i], ',')[0]), 100) << times[i];
  // The checkpoint's balancer is for 2 ranks: the 4-rank run starts rebalancing afresh, and says so.
  EXPECT_NE(r.out.find("semlb sim: restart: the checkpoint's balancer is for 2 ranks"), std::string::npos) << r.out;
  EXPECT_EQ(nlohmann::json::parse(split(read_file(dir + "/second/trace.jsonl"), '\n')[0])["event"], 0);
}

// With modelled rank times the decisions are reproducible, so a run split by a checkpoint makes the same
// decisions as the run made in one go: trace.jsonl line for line (event numbers continue, the policy's
// history continues) and the final state bit for bit, with the checkpoint at an event (holt, learned_repartition)
// and between two events (gru).
TEST(Decomposition, ARestartContinuesTheBalancerLineForLine) {
  for (const auto& [policy, split_at] :
       std::vector<std::pair<std::string, int>>{{"holt", 150}, {"gru", 125}, {"learned_repartition", 150}}) {
    const auto dir = fresh_dir("decomposition_balancer_" + policy);
    const std::string args = kArgs + " --set decomposition.timing=modelled --set decomposition.policy=" + policy;
    auto r = run(mpirun_sim(3) + args + " --steps 300 --out " + dir + "/straight");
    ASSERT_EQ(r.rc, 0) << r.out;
    r = run(mpirun_sim(3) + args + " --steps " + std::to_string(split_at) +
            " --set output.checkpoint_every=" + std::to_string(split_at) + " --out " + dir + "/split");
    ASSERT_EQ(r.rc, 0) << r.out;
    r = run(mpirun_sim(3) + args + " --steps 300 --restart " + dir + "/split/checkpoint.h5 --out " + dir + "/split");
    ASSERT_EQ(r.rc, 0) << r.out;
    EXPECT_EQ(r.out.find("restart:"), std::string::npos) << r.out;  // the balancer continued
    const auto straight = split(read_file(dir + "/straight/trace.jsonl"), '\n');
    const auto joined = split(read_file(dir + "/split/trace.jsonl"), '\n');
    ASSERT_EQ(straight.size(), 1 + 300u / 50) << policy;  // 6 events (the last at step 300), then ""
    EXPECT_EQ(joined, straight) << policy;
    EXPECT_EQ(read_state(dir + "/split/final.h5").hash(), read_state(dir + "/straight/final.h5").hash()) << policy;
    // rank_times.csv keeps the rows before the checkpoint too: with modelled times the two files are equal
    // but for the measured exchange and migration seconds (columns 3 and 4).
    auto modelled_columns = [](const std::string& file) {
      std::vector<std::string> out;
      for (const auto& line : split(read_file(file), '\n')) {
        auto f = split(line, ',');
        if (f.size() == rank_times::kColumns.size())
          out.push_back(f[0] + "," + f[1] + "," + f[2] + "," + f[5] + "," + f[6]);
      }
      return out;
    };
    EXPECT_EQ(modelled_columns(dir + "/split/rank_times.csv"), modelled_columns(dir + "/straight/rank_times.csv"))
        << policy;
    // The same run twice gives the same trace: modelled times do not depend on the launch.
    r = run(mpirun_sim(3) + args + " --steps 300 --out " + dir + "/again");
    ASSERT_EQ(r.rc, 0) << r.out;
    EXPECT_EQ(read_file(dir + "/again/trace.jsonl"), read_file(dir + "/straight/trace.jsonl")) << policy;
  }
}

TEST(Decomposition, ReplayingAnEngineTraceReproducesItsDecisions) {
  const auto dir = fresh_dir("decomposition_trace");
  auto r = run(mpirun_sim(2) + kArgs + " --steps 200 --set decomposition.params.tau=0.001 --out " + dir);
  ASSERT_EQ(r.rc, 0) << r.out;
  r = run(semlb_bin() + " replay --policy reactive --param reactive.tau=0.001 --trace " + dir + "/trace.jsonl");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto trace = split(read_file(dir + "/trace.jsonl"), '\n'), replayed = split(r.out, '\n');
  ASSERT_GE(trace.size(), 4u);
  for (size_t i = 0; i + 1 < trace.size(); ++i)
    EXPECT_EQ(nlohmann::json::parse(trace[i])["decision"], nlohmann::json::parse(replayed[i])["boundaries"]) << i;
}

// The learned controller decides in the engine as in `semlb replay` of the engine's trace (its correction state
// built from the same times and W_s, event by event).
TEST(Decomposition, ReplayingAnEngineTraceReproducesTheLearnedControllersDecisions) {
  // Modelled times from a uniform start: the imbalance the policy acts on is W_s's, the same on every launch (measured
  // wall times on a loaded machine sometimes left it nothing worth a move, and the test nothing to compare).
  const std::string kModelledFromUniform = " --set decomposition.timing=modelled --set decomposition.initial=uniform";
  const auto dir = fresh_dir("decomposition_trace_learned");
  const std::string params = " --set decomposition.params.gain=0.5 --set decomposition.params.move_cost=0.01";
  auto r = run(mpirun_sim(3) + kArgs + " --steps 300 --set decomposition.policy=learned_repartition" + params +
               kModelledFromUniform + " --out " + dir);
  ASSERT_EQ(r.rc, 0) << r.out;
  r = run(semlb_bin() +
          " replay --policy learned_repartition --param learned_repartition.gain=0.5 "
          "--param learned_repartition.move_cost=0.01 --trace " +
          dir + "/trace.jsonl");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto trace = split(read_file(dir + "/trace.jsonl"), '\n'), replayed = split(r.out, '\n');
  ASSERT_GE(trace.size(), 5u);
  bool moved = false;
  for (size_t i = 0; i + 1 < trace.size(); ++i) {
    const auto a = nlohmann::json::parse(trace[i]);
    EXPECT_EQ(a["decision"], nlohmann::json::parse(replayed[i])["boundaries"]) << i;
    moved = moved || a["decision"] != a["boundaries"];
  }
  EXPECT_TRUE(moved) << "no decision moved a boundary: the test would not see a difference";
}

TEST(Decomposition, AFailingRankStopsEveryRankNamingRankStepAndCause) {
  const auto dir = fresh_dir("decomposition_fail");
  const auto r = run(mpirun_sim(2) + kArgs + " --steps 50 --set time.dt=5 --out " + dir);
  EXPECT_EQ(r.rc, 1) << r.out;
  EXPECT_NE(r.out.find(": rank "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("displacement exceeds time.max_displacement"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/failure.h5"));
}

TEST(Decomposition, MechanicsOnlyScenesRebalanceToo) {
  const auto dir = fresh_dir("decomposition_mechanics");
  const auto r = run(
      mpirun_sim(2) + " --scene " + source("scenes/mechanics.yaml") +
      " --quiet --set tissue.cells=400 --set backend.cpu-binned.threads=1 --steps 100 --set decomposition.rebalance_every=50 --out " +
      dir);
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_EQ(split(read_file(dir + "/rank_times.csv"), '\n').size(), 2 + 2u * 2) << read_file(dir + "/rank_times.csv");
  EXPECT_EQ(split(read_file(dir + "/trace.jsonl"), '\n').size(), 3u);
}

TEST(Decomposition, TooManyRanksForTheDomainIsBadInput) {
  const auto dir = fresh_dir("decomposition_narrow");
  const auto r = run(mpirun_sim(2) + " --scene " + source("scenes/epidermis.yaml") +
                     " --quiet --set tissue.cells=4 --out " + dir + "/out");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("field 'decomposition.min_width'"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

// tests/data/narrow_slabs (the reported case): two cells within the cutoff of each other in a 9 um domain
// with decomposition.min_width 0. Every rank count gives the one-device state bit for bit or is refused at
// load time naming the field; 1 and 2 ranks need no slab between neighbours and run, 3 and 4 (which hung
// and silently lost the cells' interaction) are refused, on every rank alike.
TEST(Decomposition, SlabsNarrowerThanTheGhostRegionAreRefusedOrExact) {
  const auto dir = fresh_dir("decomposition_narrow_slabs");
  const std::string args = " --scene " + source("tests/data/narrow_slabs/scene.yaml") + " --quiet";
  auto r = run(semlb_bin() + " sim" + args + " --out " + dir + "/single");
  ASSERT_EQ(r.rc, 0) << r.out;
  const State reference = read_state(dir + "/single/final.h5");
  for (int ranks : {1, 2, 3, 4}) {
    const std::string out = dir + "/np" + std::to_string(ranks);
    r = run(mpirun_sim(ranks, "", 60) + args + " --out " + out);
    if (ranks <= 2) {
      ASSERT_EQ(r.rc, 0) << ranks << " ranks: " << r.out;
      const State s = read_state(out + "/final.h5");
      EXPECT_EQ(s.position, reference.position) << ranks << " ranks";
      EXPECT_EQ(s.hash(), reference.hash()) << ranks << " ranks";
    } else {
      EXPECT_EQ(r.rc, 2) << ranks << " ranks: " << r.out;
      EXPECT_NE(r.out.find("field 'decomposition.min_width'"), std::string::npos) << r.out;
      EXPECT_NE(r.out.find("narrower than the ghost region"), std::string::npos) << r.out;
      EXPECT_EQ(r.out.find("rank "), std::string::npos) << "every rank refuses alike: " << r.out;
      EXPECT_FALSE(std::filesystem::exists(out)) << "nothing written";
    }
  }
}

// A cell reaching further than one cutoff from its slab (here 50 um long) brings ranks 0 and 2 within the
// cutoff of each other although min_width is valid: every rank stops at step 0 with the same message.
TEST(Decomposition, ACellReachingPastTheNextSlabStopsEveryRank) {
  const auto dir = fresh_dir("decomposition_long_cell");
  State s;
  s.cell_id = {0, 1};
  s.cell_type = {0, 0};
  s.cell_count = {7, 2};
  for (double x : {5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 55.0, 62.0, 64.0})
    s.position.insert(s.position.end(), {x, 5.0, 5.0});
  s.reindex();
  write_state(dir + "/long.h5", s, {});
  test::write(dir + "/scene.yaml", R"(name: long
cutoff: 8.75
domain: {lo: [0, 0, 0], hi: [90, 10, 10]}
tissue: {file: long.h5}
time: {dt: 0.01, steps: 5}
output: {log_every: 5, snapshot_every: 0, checkpoint_every: 0}
backend: {name: serial}
decomposition: {initial: uniform, policy: static}
effects: {mechanics: {}}
)");
  const auto r = run(mpirun_sim(3, "", 60) + " --scene " + dir + "/scene.yaml --quiet --out " + dir + "/out");
  EXPECT_EQ(r.rc, 1) << r.out;
  EXPECT_NE(r.out.find("step 0: ranks 0 and 2 hold elements within the cutoff"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("decomposition.min_width"), std::string::npos) << r.out;
}

// A policy that needs what the engine cannot observe (the oracle's true work) used to throw on rank 0 alone
// at the first rebalancing event while the other ranks waited: now bad input at load time.
TEST(Decomposition, APolicyTheEngineCannotFeedIsBadInputOnEveryRank) {
  const auto dir = fresh_dir("decomposition_oracle");
  for (const std::string policy : {"oracle", "lazy_oracle"}) {  // the policies that declare PolicyNeeds::true_work
    const auto r = run(mpirun_sim(2, "", 60) + kArgs + " --steps 100 --set decomposition.policy=" + policy + " --out " +
                       dir + "/out");
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_NE(r.out.find("semlb sim: --set decomposition.policy: '" + policy + "' needs the true work"),
              std::string::npos)
        << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
  }
}

// An error on one rank alone, in the middle of a step with its ghost bands in flight (SEMLB_FAULT_INJECT=RANK:STEP),
// ends the whole job within seconds with one line naming the rank and the cause; the last complete checkpoint stays
// readable.
TEST(Decomposition, AnErrorOnOneRankAloneEndsTheJobNamingTheRank) {
  for (int rank : {0, 2}) {
    const auto dir = fresh_dir("decomposition_fault_" + std::to_string(rank));
    const auto r = run(mpirun_sim(3, "SEMLB_FAULT_INJECT=" + std::to_string(rank) + ":25", 60) + kArgs +
                       " --steps 100 --set output.checkpoint_every=10 --out " + dir);
    EXPECT_LT(r.seconds, 30) << r.out;
    EXPECT_NE(r.rc, 0) << r.out;
    EXPECT_NE(r.rc, 124) << "timed out: " << r.out;
    EXPECT_NE(r.out.find("semlb sim: rank " + std::to_string(rank) + ": step 25: fault injected by SEMLB_FAULT_INJECT"),
              std::string::npos)
        << r.out;
    ASSERT_TRUE(std::filesystem::exists(dir + "/checkpoint.h5")) << r.out;
    EXPECT_EQ(read_state(dir + "/checkpoint.h5").step, 20);
    EXPECT_FALSE(std::filesystem::exists(dir + "/final.h5"));
  }
}

// epidermis at dt = 0.2 h fails at step 0. failure.h5 is the state of that step, labelled with it: the same
// whether the run was to stop at step 5 or 100 (noise used to keep moving the elements until the check) and
// on 2 ranks as on one device (the other rank used to keep integrating).
TEST(Decomposition, FailureStateIsTheFailingStepOnAnyRankCount) {
  const auto dir = fresh_dir("decomposition_failure_state");
  const std::string args = " --scene " + source("scenes/epidermis.yaml") +
                           " --quiet --set time.dt=0.2 --set tissue.cells=60 --set backend.cpu-binned.threads=1";
  std::vector<State> states;
  for (const std::string steps : {"5", "100"}) {
    const std::string out = dir + "/single_" + steps;
    const auto r = run(within(120) + semlb_bin() + " sim" + args + " --set time.steps=" + steps + " --out " + out);
    ASSERT_EQ(r.rc, 1) << r.out;
    ASSERT_NE(r.out.find(": step 0: element"), std::string::npos) << r.out;
    states.push_back(read_state(out + "/failure.h5"));
  }
  const auto r = run(mpirun_sim(2, "", 120) + args + " --set time.steps=100 --out " + dir + "/np2");
  ASSERT_EQ(r.rc, 1) << r.out;
  ASSERT_NE(r.out.find(": step 0: element"), std::string::npos) << r.out;
  states.push_back(read_state(dir + "/np2/failure.h5"));
  for (size_t k = 0; k < states.size(); ++k) {
    EXPECT_EQ(states[k].step, 0) << k;
    EXPECT_EQ(states[k].time, 0.0) << k;
    EXPECT_EQ(states[k].position, states[0].position) << k;
    EXPECT_EQ(states[k].hash(), states[0].hash()) << k;
  }
}

}  // namespace
}  // namespace semlb::engine
