// Resumable sweep: runs every job of a manifest into one CSV; an interrupted sweep (even kill -9)
// resumes where it stopped, never losing or duplicating a row. Launchers (local, slurm) registered by name.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "manifest.hpp"
#include "runner.hpp"

namespace semlb::experiments {

// The `slurm` launcher's settings (sbatch options; docs/experiments.md "Slurm").
struct SlurmOptions {
  std::string partition, time, account;
  int gpus_per_rank = 0;                 // > 0: --gpus-per-task for every rank of an engine row
  std::vector<std::string> sbatch_args;  // each written as an `#SBATCH ARG` line
  bool dry_run = false;                  // print the batch script, submit nothing
  bool wait = true;                      // false: return after submitting (a rerun collects)
  int array_throttle = 0;                // > 0: at most N array tasks at once (`--array=LIST%N`)
  std::string task;                      // non-empty: an array task, these job indices ("3,4") into part files
  std::string command;                   // `semlb sweep ...` as given, less launcher-only flags: the task's command
};

struct SweepOptions {
  std::string results_dir = "results";
  int jobs = 1;               // worker threads
  RunOptions run;
  bool progress = true;
  std::string git_revision = "unknown";
  std::string command_line;  // recorded beside the results when the manifest has no file
  bool fresh = false;        // discard the rows of an interrupted run instead of resuming it
  std::string launcher = "local";
  SlurmOptions slurm;
};

struct SweepSummary {
  std::string csv_path;
  size_t rows = 0, resumed = 0, ran = 0;
  bool finished = true;  // false: the slurm launcher submitted jobs and returned (--no-wait) or printed (--dry-run)
};

// One manifest's jobs, their CSV layout and the finished rows of OUTPUT.partial: what every launcher shares.
// The rows of job i are `rows(i)` (one CSV line per runner row, sweep key columns first).
class SweepPlan {
 public:
  // What the plan does with RESULTS/OUTPUT.partial: resume it (create RESULTS/, start it afresh with o.fresh,
  // drop a torn last line), only read it if it exists (--dry-run), or leave it alone (an array task).
  enum class Partial { resume, read_only, ignore };
  // Expands and checks every job (InputError before anything runs), then handles OUTPUT.partial as `partial`
  // says. InputError when its header is not this manifest's.
  SweepPlan(const Manifest& m, const SweepOptions& o, Partial partial = Partial::resume);
  const Manifest& manifest() const { return m_; }
  const std::vector<Job>& jobs() const { return jobs_; }
  const RunOptions& run_options() const { return run_; }
  const Runner& runner() const { return *runner_; }
  const std::string& csv_path() const { return csv_; }
  const std::string& partial_path() const { return partial_; }
  std::string header() const;  // the CSV header line
  bool done(size_t i) const;   // job i's rows are in OUTPUT.partial
  // Runs job i (the runner) and returns its CSV lines; does not record them.
  std::string rows(size_t i) const;
  // Appends job i's lines to OUTPUT.partial in one write(2) and records them; a job already done is skipped
  // (returns false), so collecting the same rows twice never duplicates them.
  bool record(size_t i, const std::string& lines);
  // Job i's lines from a CSV written by `header() + rows(i)` (an array task's part file); InputError naming the
  // file when its header or a row's key is not job i's.
  std::string rows_from_file(size_t i, const std::string& path) const;
  // Writes OUTPUT in job order (every job must be done), removes OUTPUT.partial, copies the manifest beside it.
  void finish(const std::vector<std::string>& overrides, const SweepOptions& o) const;

 private:
  struct Layout {
    std::vector<std::string> header, axes, extra_axes;
  };
  std::string key(size_t i) const;
  std::map<std::string, std::string> read_rows(const std::string& path, std::vector<std::string>& order) const;
  Manifest m_;
  std::unique_ptr<Runner> runner_;
  std::vector<Job> jobs_;
  RunOptions run_;
  Layout layout_;
  std::string csv_, partial_;
  std::map<std::string, std::string> done_;  // job key -> its lines
};

// Rows are appended to RESULTS/OUTPUT.partial as they finish (one write per job); when all jobs are done the
// file is rewritten in job order and renamed to RESULTS/OUTPUT. A copy of the manifest with the profile,
// overrides and git revision is written beside it. An existing .partial (an interrupted run) is resumed;
// a finished OUTPUT is recomputed. Runs through the launcher o.launcher (InputError naming it if unknown).
SweepSummary run_sweep(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o);

// Launchers by name (`--launcher`): "local" (worker threads on this machine) and "slurm" (slurm_launcher.cpp).
using Launcher = std::function<SweepSummary(const Manifest&, const std::vector<std::string>&, const SweepOptions&)>;
struct LauncherRegistrar {
  LauncherRegistrar(const std::string& name, Launcher launcher);
};
std::vector<std::string> launcher_names();

}  // namespace semlb::experiments
