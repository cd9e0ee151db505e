// Resumable sweep: runs every job of a manifest into one CSV; an interrupted sweep (even kill -9)
// resumes where it stopped, never losing or duplicating a row.
#pragma once
#include <string>

#include "manifest.hpp"
#include "runner.hpp"

namespace semlb::experiments {

struct SweepOptions {
  std::string results_dir = "results";
  int jobs = 1;               // worker threads
  RunOptions run;
  bool progress = true;
  std::string git_revision = "unknown";
  std::string command_line;  // recorded beside the results when the manifest has no file
  bool fresh = false;        // discard the rows of an interrupted run instead of resuming it
};

struct SweepSummary {
  std::string csv_path;
  size_t rows = 0, resumed = 0, ran = 0;
};

// Rows are appended to RESULTS/OUTPUT.partial as they finish (one write per job); when all jobs are done the
// file is rewritten in job order and renamed to RESULTS/OUTPUT. A copy of the manifest with the profile,
// overrides and git revision is written beside it. An existing .partial (an interrupted run) is resumed;
// a finished OUTPUT is recomputed.
SweepSummary run_sweep(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o);

}  // namespace semlb::experiments
