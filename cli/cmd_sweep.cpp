// `semlb sweep MANIFEST`: run an experiment manifest (resumable) into RESULTS/<output>.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "commands.hpp"
#include "result_table.hpp"
#include "common/errors.hpp"
#include "common/version.hpp"
#include "experiments/sweep.hpp"

namespace semlb::cli {

Action add_sweep(CLI::App& app) {
  struct Opts {
    std::string manifest, profile, results = "results";
    std::vector<std::string> sets;
    int jobs = 0;
    bool no_timing = false, quiet = false, keep_runs = false, no_wait = false, wait = false, check = false;
    std::string launcher = "local";
    experiments::SlurmOptions slurm;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("sweep", "Run an experiment manifest; rerunning resumes an interrupted sweep");
  sub->add_option(
         "manifest", o->manifest,
         "Manifest file (YAML), e.g. experiments/controller_eval.yaml; its runner: " + registered_list("runners"))
      ->required();
  sub->add_option("--profile", o->profile, "Profile (small, paper); default: small when the manifest has it");
  sub->add_option("--set", o->sets, "Override KEY=VALUE (an axis takes a comma list or A-B range; repeatable)");
  sub->add_option("--results", o->results, "Results directory")->capture_default_str();
  sub->add_option("--jobs", o->jobs, "Worker threads (default: all cores)")->check(strict_integer(0, 4096));
  sub->add_flag("--no-timing", o->no_timing, "Write wall-clock columns as 0 (byte-identical reruns)");
  sub->add_flag("--quiet", o->quiet, "No progress line");
  sub->add_flag("--check", o->check,
                "Expand the manifest and check every job as its runner would (files, rank counts, settings); run and "
                "write nothing (exit 2 naming the field on a bad job)");
  sub->add_flag("--wait", o->wait,
                "When another sweep is writing the results folder, wait for it (default: exit 2 naming it)");
  sub->add_flag(
      "--keep-runs", o->keep_runs,
      "Keep each job's run files (engine MPI runs: scene.yaml, run.csv, rank_times.csv, trace.jsonl) under runs/ beside the CSV");
  std::string names;
  for (const auto& n : experiments::Launchers::names()) names += (names.empty() ? "" : ", ") + n;
  sub->add_option("--launcher", o->launcher, "Where the jobs run: " + names)->capture_default_str();
  const std::string slurm = "Slurm (--launcher slurm)";
  std::vector<CLI::Option*> slurm_only = {
      sub->add_option("--partition", o->slurm.partition, "Slurm partition")->group(slurm),
      sub->add_option("--time", o->slurm.time, "Time limit of each array task, HH:MM:SS")->group(slurm),
      sub->add_option("--account", o->slurm.account, "Slurm account")->group(slurm),
      sub->add_option("--gpus-per-rank", o->slurm.gpus_per_rank, "GPUs per MPI rank (--gpus-per-task)")
          ->check(strict_integer(1, 64))
          ->group(slurm),
      sub->add_option("--sbatch-arg", o->slurm.sbatch_args,
                      "Extra #SBATCH line, e.g. --sbatch-arg=--gres=gpu:4 (repeatable)")
          ->group(slurm),
      sub->add_flag("--dry-run", o->slurm.dry_run, "Print the batch script; submit nothing")->group(slurm),
      sub->add_flag("--no-wait", o->no_wait, "Return after submitting; rerun the same command to collect")
          ->group(slurm),
      sub->add_option("--array-throttle", o->slurm.array_throttle, "At most N array tasks at once")
          ->check(strict_integer(1, 1000000))
          ->group(slurm),
      sub->add_option("--task", o->slurm.task, "Run these jobs (an array task: INDEX,INDEX,...) into part files")
          ->group("")};
  return [o, sub, slurm_only] {
    if (!*sub) return -1;  // not the chosen subcommand
    if (o->launcher != "slurm")
      for (const auto* opt : slurm_only)
        if (opt->count()) throw InputError(opt->get_name() + ": only with --launcher slurm");
    const auto m = experiments::load_manifest(o->manifest, o->profile, o->sets);
    experiments::SweepOptions so;
    so.results_dir = o->results;
    so.jobs = o->jobs > 0 ? o->jobs : std::max(1u, std::thread::hardware_concurrency());
    so.run.timing = !o->no_timing;
    if (o->keep_runs) so.run.trace_dir = (std::filesystem::path(o->results) / m.output).parent_path() / "runs";
    so.progress = !o->quiet;
    so.git_revision = version_string();  // "0.1.0 (git REV)" in every manifest copy
    so.launcher = o->launcher;
    so.slurm = o->slurm;
    so.slurm.wait = !o->no_wait;
    so.wait = o->wait;
    if (o->check) {
      const experiments::SweepPlan plan(m, so, experiments::SweepPlan::Partial::ignore);
      std::cerr << o->manifest << (m.profile.empty() ? "" : " (profile " + m.profile + ")") << ": "
                << plan.jobs().size() << " jobs checked\n";
      return 0;
    }
    const auto sum = experiments::run_sweep(m, o->sets, so);
    if (sum.finished) {  // a job may write several CSV rows (one per interval and rank, per launch, ...)
      std::ifstream csv(sum.csv_path);
      const long lines = std::count(std::istreambuf_iterator<char>(csv), std::istreambuf_iterator<char>(), '\n');
      std::vector<std::string> keys = {"policy", "ranks"};  // then the manifest's axes but the seeds and launches
      for (const auto& a : m.axis_names())
        if (a != "seed" && a != "launch") keys.push_back(a);
      if (!o->quiet) std::cerr << result_table(sum.csv_path, keys);
      std::cerr << "wrote " << sum.csv_path << " (" << sum.rows << " jobs, " << sum.resumed << " resumed; "
                << std::max(0L, lines - 1) << " rows)\n";
    }
    return 0;
  };
}

}  // namespace semlb::cli
