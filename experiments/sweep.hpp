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

namespace semlb {
class DirLock;
}

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
  int jobs = 1;  // worker threads
  RunOptions run;
  bool progress = true;
  std::string git_revision = "unknown";
  std::string command_line;  // recorded beside the results when the manifest has no file
  bool fresh = false;        // discard the rows of an interrupted run instead of resuming it
  bool wait = false;         // wait for a sweep holding the results folder instead of exiting 2 (--wait)
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
  // Expands and checks every job (InputError before anything runs), computes each job's settings digest, then
  // handles OUTPUT.partial as `partial` says; to resume it, first locks OUTPUT's folder (common/dir_lock.hpp:
  // InputError naming the holder when another process has it, unless o.wait) for the plan's lifetime. Rows whose
  // digest is not their job's are dropped (and said so on stderr): those jobs run again. InputError when the
  // header is not this manifest's.
  SweepPlan(const Manifest& m, const SweepOptions& o, Partial partial = Partial::resume);
  ~SweepPlan();
  const Manifest& manifest() const { return m_; }
  const std::vector<Job>& jobs() const { return jobs_; }
  const RunOptions& run_options() const { return run_; }
  const Runner& runner() const { return *runner_; }
  const std::string& csv_path() const { return csv_; }
  const std::string& partial_path() const { return partial_; }
  std::string header() const;  // the CSV header line
  // OUTPUT.partial's (and part files') header: `settings_digest,` then header(); each row starts with its job's digest
  std::string partial_header() const;
  /// Job i's axes as `KEY=VALUE KEY=VALUE` (progress lines).
  std::string label(size_t i) const;
  bool done(size_t i) const;  // job i's rows, made with its settings, are in OUTPUT.partial
  const std::string& digest(size_t i) const { return digests_[i]; }  // job i's settings digest (16 hex digits)
  // Runs job i (the runner) and returns its CSV lines, each starting with the job's digest; does not record them.
  std::string rows(size_t i) const;
  // Appends job i's lines to OUTPUT.partial in one write(2) and records them; a job already done is skipped
  // (returns false), so collecting the same rows twice never duplicates them.
  bool record(size_t i, const std::string& lines);
  // Job i's lines from a CSV written by `partial_header() + rows(i)` (an array task's part file); InputError naming
  // the file when its header, a row's key or its settings digest is not job i's.
  std::string rows_from_file(size_t i, const std::string& path) const;
  // Writes OUTPUT in job order without the digest column (every job must be done), removes OUTPUT.partial, copies
  // the manifest beside it.
  void finish(const std::vector<std::string>& overrides, const SweepOptions& o) const;

 private:
  struct Layout {
    std::vector<std::string> header, axes, extra_axes;
  };
  struct Rows {
    std::string digest, lines;  // a job's rows (digest first on each line) and their digest
  };
  std::string key(size_t i) const;
  std::map<std::string, Rows> read_rows(const std::string& path, std::vector<std::string>& order) const;
  // The rows of `found` whose digest is their job's (job key -> lines); counts the others in *stale.
  std::map<std::string, std::string> current(const std::map<std::string, Rows>& found, size_t* stale) const;
  Manifest m_;
  std::unique_ptr<Runner> runner_;
  std::vector<Job> jobs_;
  std::vector<std::string> digests_;  // per job
  RunOptions run_;
  Layout layout_;
  std::string csv_, partial_;
  std::map<std::string, std::string> done_;  // job key -> its lines
  std::unique_ptr<DirLock> lock_;            // held while resuming into OUTPUT's folder
};

// Rows are appended to RESULTS/OUTPUT.partial as they finish (one write per job); when all jobs are done the
// file is rewritten in job order and renamed to RESULTS/OUTPUT. A copy of the manifest with the profile,
// overrides and git revision is written beside it. An existing .partial (an interrupted run) is resumed;
// a finished OUTPUT is recomputed. Runs through the launcher o.launcher (InputError naming it if unknown).
SweepSummary run_sweep(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o);

// Launchers by name (`--launcher`): "local" (worker threads on this machine) and "slurm" (slurm_launcher.cpp).
using Launcher = std::function<SweepSummary(const Manifest&, const std::vector<std::string>&, const SweepOptions&)>;
// A registered launcher: `const Registrar<LauncherInfo> registrar("name", {launcher});` (common/registry.hpp).
struct LauncherInfo {
  static constexpr const char* kKind = "launcher";
  static constexpr const char* kListed = "launchers";
  Launcher launch;
};
using Launchers = PluginKind<LauncherInfo>;

}  // namespace semlb::experiments
