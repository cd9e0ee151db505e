// The "slurm" sweep launcher: the unfinished jobs as one Slurm job array (each task runs one or more jobs and
// writes each job's rows to its own part file); the sweep waits (squeue + part files), collects, assembles OUTPUT.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "common/errors.hpp"
#include "common/process.hpp"
#include "common/progress_line.hpp"
#include "common/text_io.hpp"
#include "sweep.hpp"

namespace semlb::experiments {
namespace {

namespace fs = std::filesystem;

// Beside OUTPUT: OUTPUT.slurm/{sweep.sbatch, jobs, parts/JOB.csv, logs/JOBID_TASK.out, runs/}.
struct Dirs {
  fs::path root, parts, logs, runs, jobs, script;
  explicit Dirs(const std::string& csv)
      : root(fs::absolute(csv + ".slurm")),
        parts(root / "parts"),
        logs(root / "logs"),
        runs(root / "runs"),
        jobs(root / "jobs"),
        script(root / "sweep.sbatch") {}
  fs::path part(size_t i) const { return parts / (std::to_string(i) + ".csv"); }
  fs::path log(const std::string& job, size_t task) const { return logs / (job + "_" + std::to_string(task) + ".out"); }
};

std::string quote(const std::string& s) {  // for /bin/sh
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs a program with its arguments (no shell: common/process.hpp); its stdout (stderr too), and throws naming
// the command when it fails.
std::string command(const std::vector<std::string>& argv) {
  const ProcessResult r = run_process(argv);
  if (r.status != 0) throw std::runtime_error(shell_words(argv) + " failed:\n" + r.output);
  return r.output;
}

// The array task's command: this binary, the same manifest, profile, overrides and output options, plus --task
// with the task's job indices (from the script's `jobs` array).
std::string task_command(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  std::string c = quote(fs::read_symlink("/proc/self/exe").string()) + " sweep " +
                  quote(fs::absolute(m.path).string()) + (m.profile.empty() ? "" : " --profile " + quote(m.profile)) +
                  " --results " + quote(fs::absolute(o.results_dir).string()) + " --launcher slurm --quiet";
  for (const auto& s : overrides) c += " --set " + quote(s);
  if (!o.run.timing) c += " --no-timing";
  if (!o.run.trace_dir.empty()) c += " --keep-runs";
  if (o.slurm.gpus_per_rank > 0) c += " --gpus-per-rank " + std::to_string(o.slurm.gpus_per_rank);
  return c + " --task \"${jobs[$SLURM_ARRAY_TASK_ID]}\"";
}

using Tasks = std::vector<std::vector<size_t>>;  // array index -> the job indices that task runs, in order

// The cluster's MaxArraySize (array indices must be below it); Slurm's default, 1001, when scontrol cannot tell.
size_t max_array_size() {
  try {
    std::stringstream ss(
        command({"timeout", "30", "scontrol", "show", "config"}));  // a broken config makes it retry for 60 s
    for (std::string line; std::getline(ss, line);)
      if (line.rfind("MaxArraySize", 0) == 0)
        return std::max(1L, parse_integer(line.substr(line.find('=') + 1).substr(1), "MaxArraySize: "));
  } catch (const std::exception&) {
  }
  return 1001;
}

// `todo` in consecutive runs of equal size (the last shorter), as few jobs per task as MaxArraySize allows.
Tasks split_tasks(const std::vector<size_t>& todo) {
  const size_t n = max_array_size(), per = (todo.size() + n - 1) / n;
  Tasks t;
  for (size_t k = 0; k < todo.size(); k += per)
    t.emplace_back(todo.begin() + k, todo.begin() + std::min(todo.size(), k + per));
  return t;
}

std::string job_list(const std::vector<size_t>& jobs) {
  std::string s;
  for (size_t k = 0; k < jobs.size(); ++k) {
    if (k) s += ',';
    s += std::to_string(jobs[k]);
  }
  return s;
}

// A value for an `#SBATCH` line: one line, no comment character sbatch would cut it at.
std::string sbatch_value(const std::string& flag, const std::string& v) {
  if (v.find_first_of("\n\r#") != std::string::npos)
    throw InputError(flag + ": '" + v + "' may not hold a newline or '#'");
  return v;
}

std::string batch_script(const SweepPlan& plan, const Tasks& tasks, const Dirs& d,
                         const std::vector<std::string>& overrides, const SweepOptions& o) {
  int ranks = 1;  // every task of an array asks for the same: the most ranks among the jobs
  size_t count = 0;
  for (const auto& t : tasks)
    for (size_t i : t) ranks = std::max(ranks, plan.runner().mpi_ranks(plan.jobs()[i])), ++count;
  std::string name = plan.manifest().name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
  const auto& s = o.slurm;
  std::ostringstream b;
  b << "#!/bin/bash\n# semlb sweep " << name << ": " << count << " of " << plan.jobs().size() << " jobs in "
    << tasks.size() << " array tasks; task K runs the jobs ${jobs[K]}\n"
    << "#SBATCH --job-name=semlb-" << name << "\n"
    << "#SBATCH --array=0-" << tasks.size() - 1 << (s.array_throttle > 0 ? "%" + std::to_string(s.array_throttle) : "")
    << "\n"
    << "#SBATCH --ntasks=" << ranks << "\n#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --output=" << sbatch_value("--results", (d.logs / "%A_%a.out").string()) << "\n";
  if (!s.partition.empty()) b << "#SBATCH --partition=" << sbatch_value("--partition", s.partition) << "\n";
  if (!s.time.empty()) b << "#SBATCH --time=" << sbatch_value("--time", s.time) << "\n";
  if (!s.account.empty()) b << "#SBATCH --account=" << sbatch_value("--account", s.account) << "\n";
  if (s.gpus_per_rank > 0) b << "#SBATCH --gpus-per-task=" << s.gpus_per_rank << "\n";
  for (const auto& a : s.sbatch_args) b << "#SBATCH " << sbatch_value("--sbatch-arg", a) << "\n";
  b << "set -euo pipefail\njobs=(";
  for (size_t k = 0; k < tasks.size(); ++k) b << (k % 16 ? " " : "\n  ") << job_list(tasks[k]);
  b << "\n)\nexec " << task_command(plan.manifest(), overrides, o) << "\n";
  return b.str();
}

// Each submission (OUTPUT.slurm/jobs, a line `JOBID TASK;TASK;...`, TASK = `INDEX,INDEX,...`): its Slurm job id
// and tasks, in submission order.
std::vector<std::pair<std::string, Tasks>> read_submissions(const Dirs& d) {
  std::vector<std::pair<std::string, Tasks>> subs;
  if (!fs::exists(d.jobs)) return subs;
  long n = 0;
  for (const auto& line : split(read_file(d.jobs.string()), '\n')) {
    ++n;
    if (line.empty()) continue;
    const auto f = split(line, ' ');
    if (f.size() != 2) throw InputError(where(d.jobs.string(), n, "") + "expected 'JOBID INDEX,INDEX;INDEX,...'");
    Tasks tasks;
    for (const auto& t : split(f[1], ';')) {
      tasks.emplace_back();
      for (const auto& x : split(t, ','))
        tasks.back().push_back(static_cast<size_t>(parse_integer(x, where(d.jobs.string(), n, "") + "index: ")));
    }
    subs.emplace_back(f[0], tasks);
  }
  return subs;
}

// Array tasks of `jobs` still in the queue: "JOBID_TASK" -> squeue state (PD, R, CG, ...).
std::map<std::string, std::string> queued(const std::set<std::string>& jobs) {
  std::map<std::string, std::string> q;
  if (jobs.empty()) return q;
  static const std::set<std::string> ended = {"CD", "F", "CA", "TO", "NF", "OOM", "BF", "DL", "PR", "RV"};
  // All of this user's jobs rather than `-j IDS`, which fails once one of them is gone from Slurm.
  std::stringstream ss(command({"squeue", "--me", "-h", "-r", "-o", "%F %K %t"}));
  for (std::string id, task, state; ss >> id >> task >> state;)
    if (jobs.count(id) && !ended.count(state)) q[id + "_" + task] = state;
  return q;
}

// Moves the finished tasks' part files into OUTPUT.partial (one append each; a job already there is skipped).
void collect(SweepPlan& plan, const Dirs& d) {
  if (!fs::exists(d.parts)) return;
  for (const auto& e : fs::directory_iterator(d.parts)) {
    const auto name = e.path().filename().string();
    if (e.path().extension() != ".csv") continue;  // a task's temporary file
    const long i = parse_integer(e.path().stem().string(), e.path().string() + ": file name: ");
    if (i < 0 || static_cast<size_t>(i) >= plan.jobs().size())
      throw InputError(e.path().string() + ": no job " + std::to_string(i) + " in this manifest; remove the file");
    plan.record(static_cast<size_t>(i), plan.rows_from_file(static_cast<size_t>(i), e.path().string()));
    fs::remove(e.path());
  }
}

// Where a job was last submitted: the Slurm job id and the array index of its task.
struct Submitted {
  std::string id;
  size_t task = 0;
  std::string name() const { return id + "_" + std::to_string(task); }
};

struct Status {
  size_t done = 0, running = 0, pending = 0;
  std::vector<size_t> failed;        // submitted, not queued, no rows
  std::map<size_t, Submitted> last;  // job index -> its latest submission
  std::set<size_t> active;           // queued or running
};

Status status(SweepPlan& plan, const Dirs& d) {
  Status st;
  std::set<std::string> ids;
  for (const auto& [id, tasks] : read_submissions(d)) {
    ids.insert(id);
    for (size_t t = 0; t < tasks.size(); ++t)
      for (size_t i : tasks[t]) st.last[i] = {id, t};
  }
  const auto q = queued(ids);  // before collecting: a task that left the queue has written its part files
  collect(plan, d);
  for (size_t i = 0; i < plan.jobs().size(); ++i) {
    if (plan.done(i)) {
      ++st.done;
      continue;
    }
    const auto it = st.last.find(i);
    if (it == st.last.end()) continue;  // never submitted
    const auto state = q.find(it->second.name());
    if (state == q.end()) {
      st.failed.push_back(i);
      continue;
    }
    st.active.insert(i);
    ++(state->second == "PD" ? st.pending : st.running);
  }
  return st;
}

// The log's line about job i ("job I failed: ..."), else its last line (e.g. Slurm's note of a time limit).
std::string log_line(const fs::path& log, size_t i) {
  if (!fs::exists(log)) return "(no log)";
  auto lines = split(read_file(log.string()), '\n');
  for (const auto& l : lines)
    if (l.find("job " + std::to_string(i) + " failed: ") != std::string::npos) return l;
  while (!lines.empty() && lines.back().empty()) lines.pop_back();
  return lines.empty() ? "(empty log)" : lines.back();
}

// One array task: its jobs in order, each job's ranks started by srun and its rows written atomically to
// parts/INDEX.csv. A failing job is reported ("job I failed: ...") and the others still run; then it throws.
SweepSummary run_task(const Manifest& m, const SweepOptions& o) {
  SweepOptions to = o;
  to.run.mpi_launcher = {"srun", "--mpi=pmix", "--kill-on-bad-exit=1", "--cpus-per-task=1"};
  if (o.slurm.gpus_per_rank > 0)
    to.run.mpi_launcher.push_back("--gpus-per-task=" + std::to_string(o.slurm.gpus_per_rank));
  to.run.mpi_launcher.push_back("--ntasks");
  const Dirs d((fs::path(o.results_dir) / m.output).string());
  to.run.scratch_dir = d.runs.string();  // shared with rank 0, which may run on another node
  const SweepPlan plan(m, to, SweepPlan::Partial::ignore);
  std::vector<size_t> jobs;
  for (const auto& x : split(o.slurm.task, ',')) {
    const long i = parse_integer(x, "--task: ");
    if (i < 0 || static_cast<size_t>(i) >= plan.jobs().size())
      throw InputError("--task: " + x + " is not a job index (the manifest has " + std::to_string(plan.jobs().size()) +
                       " jobs)");
    jobs.push_back(static_cast<size_t>(i));
  }
  fs::create_directories(d.runs);
  const char* fail = std::getenv("SEMLB_SWEEP_FAIL_JOB");  // test hook: this job index fails
  size_t failed = 0;
  for (size_t i : jobs) {
    try {
      if (fail && std::to_string(i) == fail) throw std::runtime_error("failure injected by SEMLB_SWEEP_FAIL_JOB");
      write_file_atomically(d.part(i).string(), plan.partial_header() + plan.rows(i));
    } catch (const std::exception& e) {
      std::cerr << "job " << i << " failed: " << e.what() << std::endl;
      ++failed;
    }
  }
  if (failed)
    throw std::runtime_error(std::to_string(failed) + " of this task's " + std::to_string(jobs.size()) +
                             " jobs failed");
  SweepSummary sum;
  sum.csv_path = d.parts.string();
  sum.rows = sum.ran = jobs.size();
  sum.finished = false;
  return sum;
}

SweepSummary run_slurm(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  if (m.path.empty()) throw InputError("--launcher slurm: the manifest must be a file (array tasks read it)");
  if (!o.slurm.task.empty()) return run_task(m, o);
  SweepPlan plan(m, o, o.slurm.dry_run ? SweepPlan::Partial::read_only : SweepPlan::Partial::resume);
  const Dirs d(plan.csv_path());
  SweepSummary sum;
  sum.csv_path = plan.csv_path();
  sum.rows = plan.jobs().size();
  if (o.fresh && !o.slurm.dry_run) fs::remove_all(d.root);  // an earlier run's parts and submissions too

  Status st = o.slurm.dry_run ? Status{} : status(plan, d);
  std::vector<size_t> todo;  // neither finished nor queued: never submitted, failed or cancelled
  for (size_t i = 0; i < plan.jobs().size(); ++i)
    if (!plan.done(i) && !st.active.count(i)) todo.push_back(i);
  sum.resumed = o.slurm.dry_run ? sum.rows - todo.size() : st.done;
  if (o.slurm.dry_run) {
    if (todo.empty())
      std::cerr << "every job is done; nothing to submit\n";
    else
      std::cout << batch_script(plan, split_tasks(todo), d, overrides, o);
    sum.finished = false;
    return sum;
  }
  std::string submitted;
  if (!todo.empty()) {
    for (const auto& p : {d.parts, d.logs, d.runs}) fs::create_directories(p);
    const Tasks tasks = split_tasks(todo);
    write_file_atomically(d.script.string(), batch_script(plan, tasks, d, overrides, o));
    std::string id = command({"sbatch", "--parsable", d.script.string()});
    id = id.substr(0, id.find_first_of(";\n"));  // "JOBID[;CLUSTER]"
    parse_integer(id, "sbatch --parsable: job id: ");
    std::string line = id + " ";
    for (size_t k = 0; k < tasks.size(); ++k) {
      if (k) line += ';';
      line += job_list(tasks[k]);
    }
    const std::string old = fs::exists(d.jobs) ? read_file(d.jobs.string()) : "";
    write_file_atomically(d.jobs.string(), old + line + "\n");
    submitted = id;
    std::cerr << "submitted Slurm job " << id << ": " << todo.size() << " of " << sum.rows << " jobs as array 0-"
              << tasks.size() - 1 << " (" << tasks[0].size() << " per task), logs in " << d.logs.string() << "\n";
  }
  sum.ran = todo.size();
  ProgressLine progress(o.progress);
  std::string shown;
  const auto t0 = std::chrono::steady_clock::now();
  for (bool first = true;; first = false) {
    if (!first || !submitted.empty()) st = status(plan, d);
    if (o.progress) {
      std::ostringstream line;
      line << "[" << m.name << "] " << st.done << "/" << sum.rows << " jobs done, " << st.running << " running, "
           << st.pending << " pending, " << st.failed.size() << " failed";
      if (line.str() != shown) progress.show(line.str());
      shown = line.str();
    }
    if (st.active.empty() || !o.slurm.wait) break;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(1000 * std::min(10.0, 1.0 + s / 60))));
  }
  progress.close();
  if (!st.failed.empty()) {
    std::string msg = std::to_string(st.failed.size()) + " of " + std::to_string(sum.rows) +
                      " jobs failed (rerun the same command to resubmit them):";
    for (size_t i : st.failed) {
      const auto& at = st.last.at(i);
      const auto log = d.log(at.id, at.task);
      msg += "\n  job " + std::to_string(i) + ": array index " + std::to_string(at.task) + " of Slurm job " + at.id +
             " (" + at.name() + "), log " + log.string() + ": " + log_line(log, i);
    }
    throw std::runtime_error(msg);
  }
  if (!st.active.empty()) {  // --no-wait
    std::cerr << st.active.size() << " jobs queued or running; rerun the same command to collect them\n";
    sum.finished = false;
    return sum;
  }
  plan.finish(overrides, o);
  fs::remove_all(d.root);
  return sum;
}

const Registrar<LauncherInfo> slurm("slurm", {run_slurm});

}  // namespace
}  // namespace semlb::experiments
