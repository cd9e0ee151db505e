// Host<->device traffic of the loop (run.csv's bytes_h2d, bytes_d2h) on OpenCL: a decomposed run moves bytes in
// proportion to its ghost bands and migrants, not to its elements, and a one-device run without files almost none.
#include <gtest/gtest.h>

#include <map>

#include "../../run_command.hpp"
#include "../engine_fixtures.hpp"
#include "common/text_io.hpp"
#include "engine/backends/opencl.hpp"

namespace semlb::engine {
namespace {

using test::fresh_dir;
using test::run;
using test::semlb_bin;
using test::source;
using test::within;

// The epidermis scene (every cell effect on) on opencl-binned, without snapshots or checkpoints.
std::string args(long cells, long steps) {
  return " --scene " + source("scenes/epidermis.yaml") + " --quiet --set tissue.cells=" + std::to_string(cells) +
         " --set backend.name=opencl-binned --set decomposition.rebalance_every=25 --set output.snapshot_every=0"
         " --set output.checkpoint_every=0 --set output.log_every=25 --steps " +
         std::to_string(steps);
}

struct Totals {
  double bytes = 0;  // h2d + d2h over the logged rows
  long steps = 0, elements = 0;
  std::map<std::string, double> columns;  // summed over the rows
};

Totals read_run(const std::string& path) {
  const auto lines = split(read_file(path), '\n');
  const auto header = split(lines.at(0), ',');
  Totals t;
  long last = 0;
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const auto f = split(lines[i], ',');
    for (size_t c = 0; c < header.size(); ++c) t.columns[header[c]] += std::stod(f.at(c));
    last = std::stol(f[0]);
    t.elements = std::stol(f[3]);
  }
  t.steps = last;
  t.bytes = t.columns.at("bytes_h2d") + t.columns.at("bytes_d2h");
  return t;
}

// The sheet is square: 9x the cells is 9x the elements but 3x its y extent, so 3x the band across the slab
// boundary. The bytes per step must follow the band (well below the element ratio).
TEST(Traffic, DecomposedBytesPerStepFollowTheBandNotTheElements) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  const auto dir = fresh_dir("traffic_decomposed");
  std::map<long, Totals> runs;
  for (long cells : {200L, 1800L}) {
    const std::string out = dir + "/cells" + std::to_string(cells);
    const auto r = run(testing::mpirun_sim(2, "", 600) + args(cells, 50) + " --out " + out);
    ASSERT_EQ(r.rc, 0) << r.out;
    runs[cells] = read_run(out + "/run.csv");
    ASSERT_EQ(runs[cells].steps, 50);
    EXPECT_GT(runs[cells].columns.at("cells_s"), 0.0) << "the slowest rank's cell stage time on rank 0's run.csv";
  }
  const double element_ratio = static_cast<double>(runs[1800].elements) / runs[200].elements;
  const double byte_ratio = runs[1800].bytes / runs[200].bytes;
  EXPECT_GT(element_ratio, 8.0);
  EXPECT_GT(runs[200].bytes, 0.0) << "the bands cross";
  EXPECT_LT(byte_ratio, 0.5 * element_ratio)
      << runs[200].bytes << " -> " << runs[1800].bytes << " bytes, elements x" << element_ratio;
}

// One device, no files due: the state stays on the device; per step only flags, counts and the grid's box cross.
TEST(Traffic, OneDeviceWithoutFilesMovesAlmostNothing) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  const auto dir = fresh_dir("traffic_one_device");
  const auto r = run(semlb_bin() + " sim" + args(200, 50) + " --out " + dir);
  ASSERT_EQ(r.rc, 0) << r.out;
  const Totals t = read_run(dir + "/run.csv");
  ASSERT_EQ(t.steps, 50);
  // The positions alone are 32 bytes per element (double4): under 1% of one copy per step.
  EXPECT_LT(t.bytes / 50, 0.01 * 32.0 * t.elements) << t.bytes << " bytes over 50 steps, " << t.elements << " elements";
}

}  // namespace
}  // namespace semlb::engine
