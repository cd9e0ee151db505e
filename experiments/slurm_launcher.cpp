// The "slurm" sweep launcher: the unfinished jobs as one Slurm job array (array index = job index), each task
// writing its rows to its own part file; the sweep waits (squeue + part files), collects, assembles OUTPUT.
#include <sys/wait.h>
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
#include "common/text_io.hpp"
#include "sweep.hpp"

namespace semlb::experiments {
namespace {

namespace fs = std::filesystem;

// Beside OUTPUT: OUTPUT.slurm/{sweep.sbatch, jobs, parts/INDEX.csv, logs/JOBID_INDEX.out, runs/}.
struct Dirs {
  fs::path root, parts, logs, runs, jobs, script;
  explicit Dirs(const std::string& csv)
      : root(fs::absolute(csv + ".slurm")), parts(root / "parts"), logs(root / "logs"), runs(root / "runs"),
        jobs(root / "jobs"), script(root / "sweep.sbatch") {}
  fs::path part(size_t i) const { return parts / (std::to_string(i) + ".csv"); }
  fs::path log(const std::string& job, size_t i) const { return logs / (job + "_" + std::to_string(i) + ".out"); }
};

std::string quote(const std::string& s) {  // for /bin/sh
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs a command; its stdout (stderr too), and throws naming the command when it fails.
std::string command(const std::string& cmd) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) throw std::runtime_error("cannot run " + cmd);
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = pclose(p);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) throw std::runtime_error(cmd + " failed:\n" + out);
  return out;
}

// "0-3,7,9-10" for {0,1,2,3,7,9,10}.
std::string ranges(const std::vector<size_t>& v) {
  std::string s;
  for (size_t a = 0; a < v.size();) {
    size_t b = a;
    while (b + 1 < v.size() && v[b + 1] == v[b] + 1) ++b;
    s += (s.empty() ? "" : ",") + std::to_string(v[a]) + (b > a ? "-" + std::to_string(v[b]) : "");
    a = b + 1;
  }
  return s;
}

// The array task's command: this binary, the same manifest, profile, overrides and output options, plus --task.
std::string task_command(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  std::string c = quote(fs::read_symlink("/proc/self/exe").string()) + " sweep " + quote(fs::absolute(m.path).string()) +
                  (m.profile.empty() ? "" : " --profile " + quote(m.profile)) + " --results " + quote(fs::absolute(o.results_dir).string()) +
                  " --launcher slurm --quiet";
  for (const auto& s : overrides) c += " --set " + quote(s);
  if (!o.run.timing) c += " --no-timing";
  if (!o.run.trace_dir.empty()) c += " --keep-runs";
  if (o.slurm.gpus_per_rank > 0) c += " --gpus-per-rank " + std::to_string(o.slurm.gpus_per_rank);
  return c + " --task \"$SLURM_ARRAY_TASK_ID\"";
}

std::string batch_script(const SweepPlan& plan, const std::vector<size_t>& todo, const Dirs& d,
                         const std::vector<std::string>& overrides, const SweepOptions& o) {
  int ranks = 1;  // every task of an array asks for the same: the most ranks among the jobs
  for (size_t i : todo) ranks = std::max(ranks, plan.runner().mpi_ranks(plan.jobs()[i]));
  const auto& s = o.slurm;
  std::ostringstream b;
  b << "#!/bin/bash\n# semlb sweep " << plan.manifest().name << ": " << todo.size() << " of " << plan.jobs().size()
    << " jobs; array index = job index\n"
    << "#SBATCH --job-name=semlb-" << plan.manifest().name << "\n"
    << "#SBATCH --array=" << ranges(todo) << (s.array_throttle > 0 ? "%" + std::to_string(s.array_throttle) : "") << "\n"
    << "#SBATCH --ntasks=" << ranks << "\n#SBATCH --cpus-per-task=1\n"
    << "#SBATCH --output=" << (d.logs / "%A_%a.out").string() << "\n";
  if (!s.partition.empty()) b << "#SBATCH --partition=" << s.partition << "\n";
  if (!s.time.empty()) b << "#SBATCH --time=" << s.time << "\n";
  if (!s.account.empty()) b << "#SBATCH --account=" << s.account << "\n";
  if (s.gpus_per_rank > 0) b << "#SBATCH --gpus-per-task=" << s.gpus_per_rank << "\n";
  for (const auto& a : s.sbatch_args) b << "#SBATCH " << a << "\n";
  b << "set -euo pipefail\nexec " << task_command(plan.manifest(), overrides, o) << "\n";
  return b.str();
}

// Slurm job id -> the job indices it was submitted for, in submission order (OUTPUT.slurm/jobs).
std::vector<std::pair<std::string, std::vector<size_t>>> read_submissions(const Dirs& d) {
  std::vector<std::pair<std::string, std::vector<size_t>>> subs;
  if (!fs::exists(d.jobs)) return subs;
  long n = 0;
  for (const auto& line : split(read_file(d.jobs.string()), '\n')) {
    ++n;
    if (line.empty()) continue;
    const auto f = split(line, ' ');
    if (f.size() != 2) throw InputError(where(d.jobs.string(), n, "") + "expected 'JOBID INDEX,INDEX,...'");
    std::vector<size_t> idx;
    for (const auto& x : split(f[1], ','))
      idx.push_back(static_cast<size_t>(parse_integer(x, where(d.jobs.string(), n, "") + "index: ")));
    subs.emplace_back(f[0], idx);
  }
  return subs;
}

// Array tasks of `jobs` still in the queue: "JOBID_INDEX" -> squeue state (PD, R, CG, ...).
std::map<std::string, std::string> queued(const std::set<std::string>& jobs) {
  std::map<std::string, std::string> q;
  if (jobs.empty()) return q;
  static const std::set<std::string> ended = {"CD", "F", "CA", "TO", "NF", "OOM", "BF", "DL", "PR", "RV"};
  std::stringstream ss(command("squeue -h -r -o '%F %K %t'"));  // every job: an old id may be gone from Slurm
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

struct Status {
  size_t done = 0, running = 0, pending = 0;
  std::vector<size_t> failed;                 // submitted, not queued, no rows
  std::map<size_t, std::string> last_job;     // job index -> the Slurm job id of its latest submission
  std::set<size_t> active;
};

Status status(SweepPlan& plan, const Dirs& d) {
  Status st;
  std::set<std::string> ids;
  for (const auto& [id, idx] : read_submissions(d)) {
    ids.insert(id);
    for (size_t i : idx) st.last_job[i] = id;
  }
  const auto q = queued(ids);  // before collecting: a task that left the queue has written its part file
  collect(plan, d);
  for (size_t i = 0; i < plan.jobs().size(); ++i) {
    if (plan.done(i)) { ++st.done; continue; }
    const auto it = st.last_job.find(i);
    const auto state = it == st.last_job.end() ? q.end() : q.find(it->second + "_" + std::to_string(i));
    if (state != q.end()) {
      st.active.insert(i);
      ++(state->second == "PD" ? st.pending : st.running);
    } else if (it != st.last_job.end()) {
      st.failed.push_back(i);
    }
  }
  return st;
}

std::string last_line(const fs::path& log) {
  if (!fs::exists(log)) return "(no log)";
  auto lines = split(read_file(log.string()), '\n');
  while (!lines.empty() && lines.back().empty()) lines.pop_back();
  return lines.empty() ? "(empty log)" : lines.back();
}

// One array task: job `index` with its ranks started by srun, rows written atomically to parts/INDEX.csv.
SweepSummary run_task(const Manifest& m, const SweepOptions& o) {
  SweepOptions to = o;
  to.run.mpi_launcher = "srun --mpi=pmix --kill-on-bad-exit=1 --cpus-per-task=1" +
                        (o.slurm.gpus_per_rank > 0 ? " --gpus-per-task=" + std::to_string(o.slurm.gpus_per_rank) : "") +
                        " --ntasks";
  const Dirs d((fs::path(o.results_dir) / m.output).string());
  to.run.scratch_dir = d.runs.string();  // shared with rank 0, which may run on another node
  const SweepPlan plan(m, to, SweepPlan::Partial::ignore);
  if (o.slurm.task >= static_cast<long>(plan.jobs().size()))
    throw InputError("--task: " + std::to_string(o.slurm.task) + " is not a job index (the manifest has " +
                     std::to_string(plan.jobs().size()) + " jobs)");
  const auto i = static_cast<size_t>(o.slurm.task);
  const char* fail = std::getenv("SEMLB_SWEEP_FAIL_JOB");  // test hook: this job index fails
  if (fail && std::atol(fail) == o.slurm.task)
    throw std::runtime_error("job " + std::to_string(i) + ": failure injected by SEMLB_SWEEP_FAIL_JOB");
  fs::create_directories(d.runs);
  write_file_atomically(d.part(i).string(), plan.header() + plan.rows(i));
  SweepSummary sum;
  sum.csv_path = d.part(i).string();
  sum.rows = sum.ran = 1;
  sum.finished = false;
  return sum;
}

SweepSummary run_slurm(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  if (m.path.empty()) throw InputError("--launcher slurm: the manifest must be a file (array tasks read it)");
  if (o.slurm.task >= 0) return run_task(m, o);
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
    if (todo.empty()) std::cerr << "every job is done; nothing to submit\n";
    else std::cout << batch_script(plan, todo, d, overrides, o);
    sum.finished = false;
    return sum;
  }
  std::string submitted;
  if (!todo.empty()) {
    for (const auto& p : {d.parts, d.logs, d.runs}) fs::create_directories(p);
    write_file_atomically(d.script.string(), batch_script(plan, todo, d, overrides, o));
    std::string id = command("sbatch --parsable " + quote(d.script.string()));
    id = id.substr(0, id.find_first_of(";\n"));  // "JOBID[;CLUSTER]"
    parse_integer(id, "sbatch --parsable: job id: ");
    std::string line = id + " ";
    for (size_t k = 0; k < todo.size(); ++k) line += (k ? "," : "") + std::to_string(todo[k]);
    std::string old = fs::exists(d.jobs) ? read_file(d.jobs.string()) : "";
    write_file_atomically(d.jobs.string(), old + line + "\n");
    submitted = id;
    std::cerr << "submitted Slurm job " << id << ": " << todo.size() << " of " << sum.rows << " jobs (array "
              << ranges(todo) << "), logs in " << d.logs.string() << "\n";
  }
  sum.ran = todo.size();
  const bool tty = isatty(fileno(stderr));
  std::string shown;
  const auto t0 = std::chrono::steady_clock::now();
  for (bool first = true;; first = false) {
    if (!first || !submitted.empty()) st = status(plan, d);
    if (o.progress) {
      std::ostringstream line;
      line << "[" << m.name << "] " << st.done << "/" << sum.rows << " jobs done, " << st.running << " running, "
           << st.pending << " pending, " << st.failed.size() << " failed";
      if (line.str() != shown) std::cerr << (tty ? "\r" : "") << line.str() << (tty ? "" : "\n") << std::flush;
      shown = line.str();
    }
    if (st.active.empty() || !o.slurm.wait) break;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(1000 * std::min(10.0, 1.0 + s / 60))));
  }
  if (o.progress && tty) std::cerr << "\n";
  if (!st.failed.empty()) {
    std::string msg = std::to_string(st.failed.size()) + " of " + std::to_string(sum.rows) +
                      " jobs failed (rerun the same command to resubmit them):";
    for (size_t i : st.failed) {
      const std::string& id = st.last_job.at(i);
      msg += "\n  job " + std::to_string(i) + ": array index " + std::to_string(i) + " of Slurm job " + id + " (" + id +
             "_" + std::to_string(i) + "), log " + d.log(id, i).string() + ": " + last_line(d.log(id, i));
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

const LauncherRegistrar slurm("slurm", run_slurm);

}  // namespace
}  // namespace semlb::experiments
