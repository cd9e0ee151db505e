// `semlb sim` and `semlb bench engine` from the command line: outputs, exit codes, no partial output.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>

#include "../run_command.hpp"

namespace semlb::test {
namespace {

namespace fs = std::filesystem;

TEST(CliSim, WritesFinalStateSnapshotsXdmfRunCsvAndSceneCopy) {
  const auto dir = fresh_dir("cli_sim");
  const auto r = run(semlb_bin() + " sim --scene " + source("scenes/epidermis.yaml") + " --out " + dir +
                     "/out --steps 100 --set tissue.cells=20 --set output.snapshot_every=50 --quiet");
  ASSERT_EQ(r.rc, 0) << r.out;
  for (const char* f : {"final.h5", "final.xmf", "run.csv", "scene.yaml", "snapshots.xmf",
                        "snapshots/step_000000000.h5", "snapshots/step_000000050.h5", "snapshots/step_000000100.h5"})
    EXPECT_TRUE(fs::exists(dir + "/out/" + f)) << f;
  EXPECT_EQ(slurp(dir + "/out/run.csv").substr(0, 40), "step,time_h,cells,elements,wall_s,mechan");
  // the end-of-run breakdown and the last line in log.txt, after the command line, also with --quiet
  const std::string log = slurp(dir + "/out/log.txt");
  EXPECT_EQ(log.rfind("# ", 0), 0u) << log;
  EXPECT_NE(log.find(" sim --scene "), std::string::npos) << log;
  EXPECT_NE(log.find("\nLoop time of "), std::string::npos) << log;
  EXPECT_NE(log.find("\nsemlb sim: 100 steps, "), std::string::npos) << log;
  EXPECT_EQ(r.out.find("Loop time of"), std::string::npos) << "--quiet prints the last line only: " << r.out;
  EXPECT_NE(slurp(dir + "/out/scene.yaml").find("cells: 20"), std::string::npos);
  const auto h5 = run("h5ls -r " + dir + "/out/final.h5");
  for (const char* d : {"/elements/position", "/elements/cell", "/cells/type"})
    EXPECT_NE(h5.out.find(d), std::string::npos) << h5.out;
}

// output.final: false writes no final state (nor its index), removes an earlier run's from DIR, and says so, on one
// rank and on two; its last line (the ranks' totals) and run.csv's last row count the cells and elements that a run
// writing final.h5 counts.
TEST(CliSim, OutputFinalFalseWritesNoFinalState) {
  const auto dir = fresh_dir("cli_sim_no_final");
  const std::string args =
      " sim --scene " + source("scenes/epidermis.yaml") + " --steps 40 --set tissue.cells=20 --quiet";
  const auto with = run(semlb_bin() + args + " --out " + dir + "/with");
  ASSERT_EQ(with.rc, 0) << with.out;
  EXPECT_NE(with.out.find("/with/final.h5"), std::string::npos) << with.out;
  const auto counts = [](const std::string& out) {  // "semlb sim: 40 steps, C cells, E elements"
    const auto at = out.find("semlb sim: 40 steps, ");
    return at == std::string::npos ? std::string("none") : out.substr(at, out.find(" in ", at) - at);
  };
  const auto last_row = [](const std::string& csv) {  // its cells and elements
    std::stringstream row(csv.substr(csv.rfind('\n', csv.size() - 2) + 1));
    std::string step, time, cells, elements;
    std::getline(row, step, ',');
    std::getline(row, time, ',');
    std::getline(row, cells, ',');
    std::getline(row, elements, ',');
    return cells + "," + elements;
  };
  const std::string mpi = SEMLB_MPIEXEC " --oversubscribe -np 2 ";
  for (const std::string& launcher : {semlb_bin(), mpi + semlb_bin()}) {
    const std::string out = dir + (launcher == semlb_bin() ? "/one" : "/two");
    const std::string earlier = " sim --scene " + source("scenes/epidermis.yaml") + " --steps 5 --set tissue.cells=20";
    ASSERT_EQ(run(semlb_bin() + earlier + " --quiet --out " + out).rc, 0);  // an earlier run's final.h5 in DIR
    ASSERT_TRUE(fs::exists(out + "/final.h5"));
    const auto r = run("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + within(120) + launcher + args +
                       " --set output.final=false --out " + out);
    ASSERT_EQ(r.rc, 0) << r.out;
    EXPECT_FALSE(fs::exists(out + "/final.h5")) << out;
    EXPECT_FALSE(fs::exists(out + "/final.xmf")) << out;
    EXPECT_EQ(counts(r.out), counts(with.out)) << r.out;
    EXPECT_NE(r.out.find("; output.final: false"), std::string::npos) << r.out;
    EXPECT_EQ(last_row(slurp(out + "/run.csv")), last_row(slurp(dir + "/with/run.csv"))) << out;
  }
}

// The end of a run, as LAMMPS ends one: the loop time, element-steps per second and a line per phase with its
// min / avg / max over the ranks, its share of the loop and its imbalance; then the last line. --quiet keeps the last
// line only. On 2 ranks the ghost exchange and migration get their lines and the ranks' spread shows.
TEST(CliSim, EndsWithTheLoopTimeAndAPhaseBreakdown) {
  const auto dir = fresh_dir("cli_sim_breakdown");
  const std::string args = " --scene " + source("scenes/epidermis.yaml") + " --steps 40 --set tissue.cells=20";
  const auto r = run(semlb_bin() + " sim" + args + " --out " + dir + "/one");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_TRUE(std::regex_search(
      r.out, std::regex(R"(\nLoop time of [0-9.e+-]+ s on 1 rank for 40 steps with [0-9]+ elements at the end\n)")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(\nPerformance: [0-9.e+]+ element-steps/s, [0-9.e+-]+ ms/step\n)")))
      << r.out;
  EXPECT_NE(r.out.find("phase      |    min (s) |    avg (s) |    max (s) |  %loop | imbalance %\n"), std::string::npos)
      << r.out;
  const std::string number = R"( +[0-9.e+-]+ )";
  for (const char* phase : {"mechanics", "integrate", "cells"})  // one device: min = avg = max, no imbalance
    EXPECT_TRUE(
        std::regex_search(r.out, std::regex(std::string("\n") + phase + " +\\|(" + number + "\\|){4} +0\\.0\n")))
        << phase << "\n"
        << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(\noutput +\| +\| +[0-9.e+-]+ +\| +\| +[0-9.]+ \| +\(rank 0\)\n)")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(\nother +\| +\| +[0-9.e+-]+ +\| )"))) << r.out;
  const auto last = r.out.substr(r.out.rfind("\n", r.out.size() - 2) + 1);
  EXPECT_EQ(last.rfind("semlb sim: 40 steps, ", 0), 0u) << last;
  // What the user waited for outside the loop: the start with its parts, the end, the process; the last line gives
  // the process's seconds as start + loop + end, each >= 0, and the start at least its parts.
  std::smatch st, tail;
  ASSERT_TRUE(std::regex_search(
      r.out, st,
      std::regex(
          R"(\nStart ([0-9.e+-]+) s \(load ([0-9.e+-]+) s, tissue ([0-9.e+-]+) s, device ([0-9.e+-]+) s\); end ([0-9.e+-]+) s \(final\.h5 and the closing files ([0-9.e+-]+) s\); process ([0-9.e+-]+) s\n)")))
      << r.out;
  EXPECT_GT(std::stod(st[2]), 0.0) << st[0];  // loading the program is part of every start
  EXPECT_GE(std::stod(st[1]) + 0.011, std::stod(st[2]) + std::stod(st[3]) + std::stod(st[4])) << st[0];  // /proc: 10 ms
  EXPECT_GE(std::stod(st[5]) + 0.011, std::stod(st[6])) << st[0];
  ASSERT_TRUE(std::regex_search(
      last, tail,
      std::regex(
          R"(elements in ([0-9.e+-]+) s \(start ([0-9.e+-]+) s, loop ([0-9.e+-]+) s, end ([0-9.e+-]+) s\) on )")))
      << last;
  for (int k = 2; k <= 4; ++k) EXPECT_GE(std::stod(tail[k]), 0.0) << last;
  EXPECT_NEAR(std::stod(tail[1]), std::stod(tail[2]) + std::stod(tail[3]) + std::stod(tail[4]), 0.01) << last;
  // The phases' shares and output and other add up to the loop (other is what the timers do not cover).
  double share = 0;
  std::smatch m;
  for (auto it = r.out.cbegin();
       std::regex_search(it, r.out.cend(), m, std::regex(R"(\| +([0-9.]+) \| +(?:[0-9.]+|\(rank 0\))? *\n)"));
       it = m.suffix().first)
    share += std::stod(m[1]);
  EXPECT_NEAR(share, 100.0, 1.0) << r.out;

  const auto q = run(semlb_bin() + " sim" + args + " --quiet --out " + dir + "/quiet");
  ASSERT_EQ(q.rc, 0) << q.out;
  EXPECT_EQ(q.out.find("Loop time"), std::string::npos) << q.out;
  EXPECT_NE(q.out.find("semlb sim: 40 steps, "), std::string::npos) << q.out;

  const std::string mpi =
      "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " SEMLB_MPIEXEC " --oversubscribe -np 2 ";
  const auto d =
      run(mpi + semlb_bin() + " sim" + args + " --set decomposition.rebalance_every=10 --out " + dir + "/two");
  ASSERT_EQ(d.rc, 0) << d.out;
  EXPECT_NE(d.out.find(" on 2 ranks for 40 steps"), std::string::npos) << d.out;
  for (const char* phase : {"mechanics", "exchange", "migration"})
    EXPECT_TRUE(
        std::regex_search(d.out, std::regex(std::string("\n") + phase + " +\\|(" + number + "\\|){4} +[0-9.]+\n")))
        << phase << "\n"
        << d.out;
  EXPECT_NE(d.out.find("\n(exchange and migration: over the 4 rebalancing intervals, to step 40; after the last one "
                       "they count in other)\n"),
            std::string::npos)
      << d.out;
  EXPECT_TRUE(
      std::regex_search(d.out, std::regex(R"(\nStart [0-9.e+-]+ s \(load [0-9.e+-]+ s, tissue [0-9.e+-]+ s, device )")))
      << d.out;
  EXPECT_EQ(d.out.find("Loop time"), d.out.rfind("Loop time")) << "printed by one rank only\n" << d.out;
  // no rebalancing interval ended in 40 steps: no exchange or migration rows (they would read 0), and a note says so
  const auto n =
      run(mpi + semlb_bin() + " sim" + args + " --set decomposition.rebalance_every=100 --out " + dir + "/none");
  ASSERT_EQ(n.rc, 0) << n.out;
  EXPECT_EQ(n.out.find("\nexchange "), std::string::npos) << n.out;
  EXPECT_NE(n.out.find("(exchange and migration: no rebalancing interval ended"), std::string::npos) << n.out;
}

TEST(CliSim, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const auto dir = fresh_dir("cli_sim_bad");
  write(dir + "/bad.yaml", "name: x\ntime:\n  dt: zero\n");
  auto r = run(semlb_bin() + " sim --scene " + dir + "/bad.yaml --out " + dir + "/out");
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.out.find("bad.yaml:3: field 'time.dt': 'zero' is not a number"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
  r = run(semlb_bin() + " sim --scene " + source("scenes/mechanics.yaml") + " --out " + dir + "/out --backend cuda");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
  r = run(semlb_bin() + " sim --scene " + source("scenes/mechanics.yaml") + " --out " + dir +
          "/out --set effects.growht={}");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
  // an OpenCL setting on a CPU backend: the backend does not use it
  r = run(semlb_bin() + " sim --scene " + source("scenes/mechanics.yaml") + " --out " + dir +
          "/out --backend cpu-binned --platform Portable");
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("backend 'cpu-binned' does not use it"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("platform"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_FALSE(fs::exists(dir + "/out"));
}

TEST(CliSim, NumericalFailureExitsOneNamingStepElementQuantityAndKeepsTheState) {
  const auto dir = fresh_dir("cli_sim_fail");
  const auto r = run(semlb_bin() + " sim --scene " + source("scenes/mechanics.yaml") + " --out " + dir +
                     "/out --steps 50 --set tissue.cells=20 --set time.dt=5 --quiet");
  EXPECT_EQ(r.rc, 1) << r.out;
  EXPECT_NE(r.out.find("mechanics.yaml: step "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("displacement exceeds time.max_displacement"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir + "/out/failure.h5"));
  EXPECT_FALSE(fs::exists(dir + "/out/final.h5"));
  const std::string log = slurp(dir + "/out/log.txt");  // the command line and the failure, as on stderr
  EXPECT_NE(log.find("--set time.dt=5"), std::string::npos) << log;
  EXPECT_NE(log.find("displacement exceeds time.max_displacement"), std::string::npos) << log;
}

// A run continued by --restart into its own folder appends to its log.txt (as to run.csv); a fresh run replaces it.
TEST(CliSim, ARestartIntoItsFolderAppendsToTheLog) {
  const auto dir = fresh_dir("cli_sim_log_restart");
  const std::string sim = semlb_bin() + " sim --scene " + source("scenes/mechanics.yaml") + " --out " + dir +
                          "/out --set tissue.cells=20 --set output.checkpoint_every=10 --quiet";
  ASSERT_EQ(run(sim + " --steps 10").rc, 0);
  const auto r = run(sim + " --steps 20 --restart " + dir + "/out/checkpoint.h5");
  ASSERT_EQ(r.rc, 0) << r.out;
  const std::string log = slurp(dir + "/out/log.txt");
  const auto first = log.find("\nsemlb sim: 10 steps, "), second = log.find("\nsemlb sim: ", first + 1);
  ASSERT_NE(first, std::string::npos) << log;
  ASSERT_NE(second, std::string::npos) << "the restart's part is missing: " << log;
  EXPECT_NE(log.find("--restart", first), std::string::npos) << log;
  ASSERT_EQ(run(sim + " --steps 5").rc, 0);
  EXPECT_EQ(slurp(dir + "/out/log.txt").find("--restart"), std::string::npos) << "a fresh run keeps the old log";
}

// With a neighbour list the breakdown gives its skin, its builds and whether it is the half list (newton).
TEST(CliSim, TheBreakdownNamesTheNeighbourListAndItsHalf) {
  const auto dir = fresh_dir("cli_sim_list");
  const std::string args = " sim --scene " + source("scenes/mechanics.yaml") +
                           " --steps 20 --set tissue.cells=20 --backend opencl-binned --set backend.skin=0.5";
  const auto full = run(semlb_bin() + args + " --out " + dir + "/full");
  if (full.rc != 0 && full.out.find("OpenCL") != std::string::npos) GTEST_SKIP() << "no OpenCL device: " << full.out;
  ASSERT_EQ(full.rc, 0) << full.out;
  EXPECT_TRUE(
      std::regex_search(full.out, std::regex(R"(\nNeighbour list: skin 0\.5 um, [0-9]+ builds over the ranks)")))
      << full.out;
  const auto half = run(semlb_bin() + args + " --set backend.newton=true --out " + dir + "/half");
  ASSERT_EQ(half.rc, 0) << half.out;
  EXPECT_NE(half.out.find("\nNeighbour list: skin 0.5 um (half: newton), "), std::string::npos) << half.out;
}

TEST(CliSim, BenchEnginePrintsElementStepsPerSecond) {
  const auto r = run(semlb_bin() + " bench engine --backends serial,cpu-binned --cells 20 --steps 3 --warmup 1");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_NE(r.out.find("elem-steps/s"), std::string::npos);
  EXPECT_NE(r.out.find("\nserial "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\ncpu-binned "), std::string::npos) << r.out;
}

// --platform goes to the rows whose backend has a device (docs/cli.md's mixed command); a key no row's backend reads
// is refused before anything is printed; --platform with no OpenCL row is refused naming it.
TEST(CliSim, BenchEngineGivesThePlatformToTheOpenClRowsAndChecksEveryRowFirst) {
  const auto mixed =
      run(semlb_bin() +
          " bench engine --backends cpu-binned,opencl-binned --cells 20 --steps 2 --warmup 1 --platform Portable");
  if (mixed.rc == 0) {  // with PoCL: both rows
    EXPECT_NE(mixed.out.find("\ncpu-binned "), std::string::npos) << mixed.out;
    EXPECT_NE(mixed.out.find("\nopencl-binned "), std::string::npos) << mixed.out;
  }
  const auto bad =
      run(semlb_bin() + " bench engine --backends serial,cpu-binned --cells 20 --steps 2 --set backend.bogus=1");
  EXPECT_EQ(bad.rc, 2) << bad.out;
  EXPECT_EQ(bad.out.find("semlb bench engine:"), std::string::npos) << "nothing printed before the error: " << bad.out;
  EXPECT_NE(bad.out.find("backend.bogus: backend 'serial' does not use it"), std::string::npos) << bad.out;
  const auto host = run(semlb_bin() + " bench engine --backends cpu-binned --cells 20 --steps 2 --platform Portable");
  EXPECT_EQ(host.rc, 2) << host.out;
  EXPECT_NE(host.out.find("--platform: backend 'cpu-binned' does not use it"), std::string::npos) << host.out;
}

// Every flag is checked before a row runs (no header, no row, exit 2), and each error names the flag given: a bad
// backend or one given twice, a tissue size outside the generator's range in any row, a setting given by a flag and a
// --set, a flag the chosen benchmark does not read.
TEST(CliSim, BenchEngineChecksEveryFlagBeforeARowAndNamesIt) {
  const std::string bench = semlb_bin() + " bench engine --steps 1 --warmup 0 ";
  for (const auto& [flags, message] : std::vector<std::pair<std::string, std::string>>{
           {"--backends serial,", "--backends: '' is not a backend (known: "},
           {"--backends serial,serial", "--backends: 'serial' is given twice"},
           {"--backends serial --cells 20,100000000", "--cells: '100000000' is outside [1, 1048576]"},
           {"--backends serial --cells 0", "--cells: '0' is outside [1, 1048576]"},
           {"--backends serial --cells -5", "--cells: '-5': is not a non-negative integer or an inclusive range"},
           {"--backends serial --cells 20 --set tissue.cells=50", "--cells: tissue.cells is also given by --set"},
           {"--backends serial --cells 20 --set 'tissue={cells: 50}'",
            "--cells: tissue.cells is also given by --set tissue; give it once"},
           {"--backends serial --cells 20 --set time.steps=5", "--set time.steps: bench engine times --steps steps"},
           {"--backends serial --cells 20 --set effects.mechanics.intra.U0=x",
            "--set effects.mechanics.intra.U0: 'x' is not a number"},
           {"--backends serial --cells 20 --set tissue.cels=1", "--set tissue.cels: unknown setting"},
           {"--backends serial --cells 20 --ranks 4", "--ranks: bench engine does not use it"},
           {"--backends serial --cells 20 --weights x.h5", "--weights: bench engine does not use it"},
           {"--backends cpu-binned --cells 20 --platform Portable",
            "--platform: backend 'cpu-binned' does not use it"}}) {
    const auto r = run(bench + flags);
    EXPECT_EQ(r.rc, 2) << flags << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << flags << "\n" << r.out;
    EXPECT_EQ(r.out.find("semlb bench engine:"), std::string::npos) << "printed before the error: " << r.out;
  }
  const auto policies = run(semlb_bin() + " bench policies --ranks 2 --events 2 --repeats 1 --cells 20");
  EXPECT_EQ(policies.rc, 2) << policies.out;
  EXPECT_NE(policies.out.find("--cells: bench policies does not use it"), std::string::npos) << policies.out;
}

// A platform or device that is not there is named where it was given.
TEST(CliSim, AMissingPlatformOrDeviceIsNamedByItsFlag) {
  const auto dir = fresh_dir("cli_sim_platform");
  const std::string sim = semlb_bin() + " sim --scene " + source("scenes/mechanics.yaml") +
                          " --backend opencl-binned --set tissue.cells=20 --steps 1 --quiet --out " + dir + "/o";
  const auto r = run(sim + " --platform NoSuchPlatform");
  if (r.out.find("no OpenCL platform found") != std::string::npos) GTEST_SKIP() << r.out;
  EXPECT_EQ(r.rc, 2) << r.out;
  EXPECT_NE(r.out.find("--platform: no platform matches 'NoSuchPlatform' (found: "), std::string::npos) << r.out;
  const auto d = run(sim + " --platform Portable --device 7");
  EXPECT_EQ(d.rc, 2) << d.out;
  EXPECT_NE(d.out.find("--device: index 7 but platform '"), std::string::npos) << d.out;
  EXPECT_FALSE(fs::exists(dir + "/o"));
}

// opencl-binned with a neighbour list: the skin and the builds per step beside ms/step, and a line with its figures.
TEST(CliSim, BenchEnginePrintsTheSkinAndTheListBuilds) {
  const auto r = run(
      semlb_bin() +
      " bench engine --backends opencl-binned --cells 20 --steps 40 --warmup 1 --set backend.opencl-binned.skin=0.5");
  if (r.rc != 0) GTEST_SKIP() << "no OpenCL platform? " << r.out;
  const size_t at = r.out.find("\nopencl-binned ");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::istringstream row(r.out.substr(at + 1));
  std::string backend, precision;
  double n, elements, seconds, rate, ms, skin, builds;
  row >> backend >> precision >> n >> elements >> seconds >> rate >> ms >> skin >> builds;
  ASSERT_TRUE(row) << r.out;
  EXPECT_EQ(skin, 0.5) << r.out;
  EXPECT_GE(builds, 0.0) << r.out;
  EXPECT_LE(builds, 1.0) << r.out;
  EXPECT_NE(r.out.find("    list: skin 0.5 um, "), std::string::npos) << r.out;
}

TEST(CliSim, BenchEnginePrintsMsPerStepAndTheRatioToAPreviousFigure) {
  const auto r =
      run(semlb_bin() + " bench engine --backends serial --cells 20,40 --steps 3 --warmup 1 --previous 1e9,1e9");
  ASSERT_EQ(r.rc, 0) << r.out;
  ASSERT_NE(r.out.find("ms/step"), std::string::npos) << r.out;
  size_t at = 0;
  for (double cells : {20.0, 40.0}) {  // row: backend precision cells elements seconds e-s/s ms skin builds ratio ...
    at = r.out.find("\nserial ", at);
    ASSERT_NE(at, std::string::npos) << r.out;
    std::istringstream row(r.out.substr(++at));
    std::string backend, precision;
    double n, elements, seconds, rate, ms, skin, builds, ratio;
    row >> backend >> precision >> n >> elements >> seconds >> rate >> ms >> skin >> builds >> ratio;
    ASSERT_TRUE(row) << r.out;
    EXPECT_EQ(skin, 0.0) << r.out;  // serial has no neighbour list
    EXPECT_EQ(builds, 0.0) << r.out;
    EXPECT_EQ(n, cells) << r.out;
    EXPECT_NEAR(ms, 1e3 * elements / rate, 1e-3 * ms) << r.out;  // both from one timing (rate to 4 digits)
    EXPECT_NEAR(seconds, 3 * ms / 1e3, 1e-4) << r.out;           // seconds printed to 4 decimals
    EXPECT_NEAR(ratio, 1e9 / ms, 0.01 * ratio) << r.out;         // previous / now
  }
  const auto wrong = run(semlb_bin() + " bench engine --backends serial --cells 20,40 --steps 1 --previous 3.5");
  EXPECT_EQ(wrong.rc, 2) << wrong.out;
  EXPECT_NE(wrong.out.find("--previous: 1 figures for 2 rows"), std::string::npos) << wrong.out;
  const auto bad = run(semlb_bin() + " bench engine --backends serial --cells 20 --steps 1 --previous 3.5ms");
  EXPECT_EQ(bad.rc, 2) << bad.out;
  EXPECT_NE(bad.out.find("--previous: '3.5ms' is not a number"), std::string::npos) << bad.out;
}

TEST(CliSim, BenchCellsTimesEachPartOfTheCellStage) {
  const auto r = run(semlb_bin() + " bench cells --backends cpu-binned --cells 300 --steps 3");
  ASSERT_EQ(r.rc, 0) << r.out;
  EXPECT_NE(r.out.find("cpu-binned double, 3"), std::string::npos) << r.out;  // cells grown from 300 by divisions
  double sum = 0, total = 0;
  for (const char* part : {"stage", "grid", "total"}) {
    const auto at = r.out.find(std::string("\n  ") + part + " ");
    ASSERT_NE(at, std::string::npos) << part << "\n" << r.out;
    const double ms = std::stod(r.out.substr(at + 3 + std::string(part).size()));
    EXPECT_GE(ms, 0.0) << part;
    (std::string(part) == "total" ? total : sum) += ms;
  }
  EXPECT_NEAR(total, sum, 0.05 + 1e-3 * sum) << r.out;  // the parts add up to the total (printed rounded)
  const auto bad =
      run(semlb_bin() + " bench cells --scene " + std::string(SEMLB_SOURCE_DIR) + "/scenes/mechanics.yaml --steps 1");
  EXPECT_EQ(bad.rc, 2) << bad.out;
  EXPECT_NE(bad.out.find("mechanics.yaml: field 'effects': the scene lists no cell effect"), std::string::npos)
      << bad.out;
}

}  // namespace
}  // namespace semlb::test
