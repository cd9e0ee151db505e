// The engine_observables runner (accuracy_development): rows per run and sample time, errors against the reference
// run, the cell stage kept in hours across time steps, and its refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "../run_command.hpp"
#include "common/text_io.hpp"

using namespace semlb::test;
namespace fs = std::filesystem;

namespace {
// 9 cells of the development scene for 2 h, sampled every hour: the reference (dt 0.05 h) and dt 0.1 h.
std::string observables_manifest(const std::string& extra) {
  return "name: obs\nrunner: engine_observables\noutput: obs.csv\ngroups:\n"
         "  - {precision: [double], dt: [0.05], cutoff: [8.75]}\n  - {precision: [double], dt: [0.1], cutoff: [8.75]}\n"
         "set:\n  scene: " +
         source("scenes/epidermis_development.yaml") +
         "\n  backend: cpu-binned\n  cells: 9\n  hours: 2\n  sample_h: 1\n  reference_dt: 0.05\n  reference_cutoff: 8.75\n" +
         extra;
}

std::vector<std::map<std::string, std::string>> rows_of(const std::string& path) {
  const auto lines = semlb::split(slurp(path), '\n');
  const auto header = semlb::split(lines.at(0), ',');
  std::vector<std::map<std::string, std::string>> rows;
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const auto f = semlb::split(lines[i], ',');
    EXPECT_EQ(f.size(), header.size()) << lines[i];
    std::map<std::string, std::string> r;
    for (size_t c = 0; c < header.size() && c < f.size(); ++c) r[header[c]] = f[c];
    rows.push_back(r);
  }
  return rows;
}
}  // namespace

// Each run gives one row per sample time (0, 1, 2 h) with steps = hours / dt; the reference's errors are 0, and
// every other row's errors are its observables minus the reference's at the same time; cells per type add up.
TEST(EngineRunners, ObservablesRowsCompareEachSampleWithTheReference) {
  const auto dir = fresh_dir("engine_observables");
  write(dir + "/m.yaml", observables_manifest("  cell_stage_h: 0.5\n"));
  const auto r =
      run(within(300) + semlb_bin() + " sweep " + dir + "/m.yaml --no-timing --quiet --results " + dir + "/out");
  ASSERT_EQ(r.rc, 0) << r.out;
  const auto rows = rows_of(dir + "/out/obs.csv");
  ASSERT_EQ(rows.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    const auto& row = rows[i];
    const bool reference = i < 3;
    EXPECT_EQ(row.at("dt"), reference ? "0.05" : "0.1");
    EXPECT_EQ(std::stod(row.at("time_h")), static_cast<double>(i % 3));
    EXPECT_EQ(std::stol(row.at("steps")), std::lround(static_cast<double>(i % 3) / std::stod(row.at("dt"))));
    EXPECT_EQ(std::stol(row.at("basal")) + std::stol(row.at("spinous")) + std::stol(row.at("granular")),
              std::stol(row.at("cells")));
    EXPECT_EQ(row.at("wall_s"), "0") << "--no-timing";
    const auto& ref = rows[i % 3];
    EXPECT_DOUBLE_EQ(std::stod(row.at("thickness_error_um")),
                     std::stod(row.at("thickness_um")) - std::stod(ref.at("thickness_um")));
    EXPECT_DOUBLE_EQ(std::stod(row.at("work_centre_error_um")),
                     std::stod(row.at("work_centre_um")) - std::stod(ref.at("work_centre_um")));
    if (reference) {
      for (const char* c : {"cells_error", "thickness_error_um", "work_centre_error_um", "work_profile_error"})
        EXPECT_EQ(row.at(c), "0") << c;
    }
    EXPECT_GE(std::stod(row.at("work_profile_error")), 0.0);
    EXPECT_LE(std::stod(row.at("work_profile_error")), 1.0);
  }
  EXPECT_EQ(rows[3].at("thickness_um"), rows[0].at("thickness_um")) << "the same tissue at 0 h";
  EXPECT_NE(rows[5].at("thickness_um"), rows[2].at("thickness_um")) << "dt 0.1 h moves the elements differently";
  EXPECT_GT(std::stod(rows[5].at("work_profile_error")), 0.0);
  EXPECT_GT(std::stod(rows[2].at("thickness_um")), std::stod(rows[0].at("thickness_um")))
      << "the sheet relaxes from its start";
}

// hours, sample_h and cell_stage_h must be whole numbers of the time step (and of samples); cell_stage_h is required.
TEST(EngineRunners, ObservablesRefuseTimesThatAreNotWholeSteps) {
  const auto dir = fresh_dir("engine_observables_bad");
  for (const auto& [extra, want] : std::vector<std::pair<std::string, std::string>>{
           {"", "m.yaml: field 'cell_stage_h': missing"},
           {"  cell_stage_h: 0.25\n",
            "m.yaml:15: field 'cell_stage_h': 0.25 h is not a whole number of steps (dt) of 0.1 h"},
           {"  cell_stage_h: 0.5\n  sample_h: 0.75\n  hours: 1.5\n",
            "field 'sample_h': 0.75 h is not a whole number of steps (dt) of 0.1 h"},
           {"  cell_stage_h: 0.5\n  hours: 3.5\n",
            "field 'hours': 3.5 h is not a whole number of samples (sample_h) of 1 h"}}) {
    std::string text = observables_manifest(extra);
    for (const char* k : {"sample_h", "hours"})  // a later key replaces the default line
      if (extra.find(k) != std::string::npos)
        text.erase(text.find(std::string("  ") + k + ": "), text.find('\n', text.find(std::string("  ") + k + ": ")) -
                                                                text.find(std::string("  ") + k + ": ") + 1);
    write(dir + "/m.yaml", text);
    fs::remove_all(dir + "/out");
    const auto r = run(within(60) + semlb_bin() + " sweep " + dir + "/m.yaml --quiet --results " + dir + "/out");
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_NE(r.out.find(want), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir + "/out")) << extra;
  }
}
