// Sweep execution: expansion, validation, resume from the .partial file, worker threads, progress line.
#include "sweep.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "common/errors.hpp"
#include "common/registry.hpp"
#include "common/text_io.hpp"

namespace semlb::experiments {
namespace fs = std::filesystem;
namespace {

std::string csv_line(const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + cells[i];
  return s + "\n";
}

// A job's value of axis A; empty when the job's axis group lacks A.
std::string axis_value(const Job& j, const std::string& a) {
  const Setting* s = j.find(a);
  return s ? s->value : "";
}

class Appender {  // one write(2) per row with O_APPEND: a kill leaves whole rows or a torn last line
 public:
  explicit Appender(const std::string& path) : fd_(::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0644)) {
    if (fd_ < 0) throw std::runtime_error(path + ": cannot open for appending");
  }
  ~Appender() { ::close(fd_); }
  void append(const std::string& line) {
    if (::write(fd_, line.data(), line.size()) != static_cast<ssize_t>(line.size()))
      throw std::runtime_error("append failed");
  }

 private:
  int fd_;
};

void copy_manifest(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o,
                   const std::string& csv) {
  std::string body, head = "# " + o.command_line + "\n";
  if (!m.path.empty()) {
    body = read_file(m.path);
    head = "# semlb sweep " + m.path + " --profile " + m.profile;
    for (const auto& s : overrides) head += " --set " + s;
    head += "\n";
  }
  head += "# git revision: " + o.git_revision + "\n";
  write_file_atomically(fs::path(csv).replace_extension(".manifest.yaml").string(), head + body);
}

class Progress {
 public:
  Progress(std::string name, size_t total, size_t resumed, bool on)
      : name_(std::move(name)), total_(total), done_(resumed), resumed_(resumed), on_(on),
        tty_(isatty(fileno(stderr))), start_(std::chrono::steady_clock::now()) {
    // A line at once, so a sweep whose first job runs long says it started (then one per finished job)
    if (on_) std::fprintf(stderr, "%s[%s] %zu/%zu jobs (%zu resumed)  starting%s", tty_ ? "\r" : "", name_.c_str(), done_,
                          total_, resumed_, tty_ ? "" : "\n");
  }
  void tick() {
    ++done_;
    if (!on_) return;
    const size_t ran = done_ - resumed_, step = std::max<size_t>(1, (total_ - resumed_) / 20);
    if (!tty_ && ran % step != 0 && done_ != total_) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double eta = ran ? s / ran * (total_ - done_) : 0.0;
    std::fprintf(stderr, "%s[%s] %zu/%zu jobs (%zu resumed)  %.1f s  ETA %.1f s%s", tty_ ? "\r" : "", name_.c_str(),
                 done_, total_, resumed_, s, eta, tty_ && done_ != total_ ? "" : "\n");
  }

 private:
  std::string name_;
  size_t total_, done_, resumed_;
  bool on_, tty_;
  std::chrono::steady_clock::time_point start_;
};

long kill_after_rows() {  // test hook: SEMLB_SWEEP_KILL_AFTER=N sends SIGKILL to itself after N new rows
  const char* v = std::getenv("SEMLB_SWEEP_KILL_AFTER");
  return v ? std::atol(v) : -1;
}

}  // namespace

SweepPlan::SweepPlan(const Manifest& m, const SweepOptions& o, Partial partial)
    : m_(m), runner_(make_runner(m.runner, m.path)), jobs_(m.expand()), run_(o.run) {
  if (run_.base_dir.empty() && !m.path.empty()) run_.base_dir = fs::path(m.path).parent_path().string();
  for (const auto& j : jobs_) runner_->check(j, m.path, run_);
  // The sweep's own key columns (axes the runner does not write) come first, then the runner's columns.
  layout_.axes = m.axis_names();
  const auto cols = runner_->columns();
  for (const auto& a : layout_.axes)
    if (std::find(cols.begin(), cols.end(), a) == cols.end()) layout_.extra_axes.push_back(a);
  layout_.header = layout_.extra_axes;
  layout_.header.insert(layout_.header.end(), cols.begin(), cols.end());

  csv_ = (fs::path(o.results_dir) / m.output).string();
  partial_ = csv_ + ".partial";
  if (partial == Partial::ignore) return;
  std::vector<std::string> order;
  if (partial == Partial::read_only) {
    if (fs::exists(partial_) && !o.fresh) done_ = read_rows(partial_, order);
    return;
  }
  fs::create_directories(fs::path(csv_).parent_path());
  if (o.fresh) fs::remove(partial_);
  // Only an interrupted run (.partial) is resumed; a finished OUTPUT is always recomputed, since the code
  // that produced it may have changed since.
  if (!fs::exists(partial_)) write_file_atomically(partial_, header());
  done_ = read_rows(partial_, order);
  std::string text = header();  // without a torn last line, so that appends start on a fresh line
  for (auto& k : order) text += done_[k];
  write_file_atomically(partial_, text);
}

std::string SweepPlan::header() const { return csv_line(layout_.header); }

std::string SweepPlan::key(size_t i) const {
  std::string k;
  for (const auto& a : layout_.axes) k += axis_value(jobs_[i], a) + '\x1f';
  return k;
}

bool SweepPlan::done(size_t i) const { return done_.count(key(i)) > 0; }

// Reads finished rows (job key -> its lines) from an earlier CSV; a torn last line (no newline) is dropped.
// A job's rows are appended in one write, so a job is either complete or (torn line aside) absent.
std::map<std::string, std::string> SweepPlan::read_rows(const std::string& path, std::vector<std::string>& order) const {
  std::map<std::string, std::string> rows;
  std::string text = read_file(path);
  if (text.empty()) return rows;
  if (text.back() != '\n') text.erase(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  std::stringstream ss(text);
  std::string line;
  std::getline(ss, line);
  if (header() != line + "\n")
    throw InputError(path + ":1: header differs from this manifest's columns; move the file away to start afresh");
  long n = 1;
  while (std::getline(ss, line)) {
    ++n;
    const auto cells = split(line, ',');
    if (cells.size() != layout_.header.size()) throw InputError(where(path, n, "") + "row has the wrong number of columns");
    std::string key;
    for (const auto& a : layout_.axes)
      key += cells[std::find(layout_.header.begin(), layout_.header.end(), a) - layout_.header.begin()] + '\x1f';
    if (!rows.count(key)) order.push_back(key);
    rows[key] += line + "\n";  // a job may have several rows
  }
  return rows;
}

std::string SweepPlan::rows(size_t i) const {
  const Job& job = jobs_[i];
  const auto columns = runner_->columns();
  std::string lines;
  for (const auto& row : runner_->run(job, run_)) {
    std::vector<std::string> cells;
    for (const auto& a : layout_.extra_axes) cells.push_back(axis_value(job, a));
    for (size_t c = 0; c < row.size(); ++c) {  // key columns keep the manifest's spelling
      const Setting* axis = std::find(layout_.axes.begin(), layout_.axes.end(), columns[c]) != layout_.axes.end()
                                ? job.find(columns[c]) : nullptr;
      cells.push_back(axis ? axis->value : row[c]);
    }
    lines += csv_line(cells);
  }
  return lines;
}

bool SweepPlan::record(size_t i, const std::string& lines) {
  if (done(i)) return false;
  Appender(partial_).append(lines);
  done_[key(i)] = lines;
  return true;
}

std::string SweepPlan::rows_from_file(size_t i, const std::string& path) const {
  std::vector<std::string> order;
  auto rows = read_rows(path, order);
  if (order.empty()) return "";  // a job without rows
  if (order.size() != 1 || order[0] != key(i))
    throw InputError(path + ": rows are not job " + std::to_string(i) + "'s of this manifest; remove the file to rerun the job");
  return rows[order[0]];
}

void SweepPlan::finish(const std::vector<std::string>& overrides, const SweepOptions& o) const {
  std::string text = header();  // job order; rows of other jobs in .partial are dropped
  for (size_t i = 0; i < jobs_.size(); ++i) text += done_.at(key(i));
  write_file_atomically(csv_, text);
  fs::remove(partial_);
  copy_manifest(m_, overrides, o, csv_);
}

namespace {

Registry<Launcher>& launchers() {
  static Registry<Launcher> r;
  return r;
}

// The local launcher: worker threads on this machine, one OUTPUT.partial append per finished job.
SweepSummary run_local(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  SweepPlan plan(m, o);
  std::vector<size_t> todo;
  for (size_t i = 0; i < plan.jobs().size(); ++i)
    if (!plan.done(i)) todo.push_back(i);
  SweepSummary sum;
  sum.csv_path = plan.csv_path();
  sum.rows = plan.jobs().size();
  sum.resumed = sum.rows - todo.size();

  Progress progress(m.name, sum.rows, sum.resumed, o.progress);
  std::mutex mu;
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  const long kill_after = kill_after_rows();
  auto worker = [&] {
    for (size_t t; (t = next++) < todo.size();) {
      try {
        const std::string lines = plan.rows(todo[t]);  // all rows of the job, appended with one write
        std::lock_guard lock(mu);
        plan.record(todo[t], lines);
        ++sum.ran;
        progress.tick();
        if (kill_after >= 0 && static_cast<long>(sum.ran) >= kill_after) std::raise(SIGKILL);
      } catch (...) {
        std::lock_guard lock(mu);
        if (!error) error = std::current_exception();
        next = todo.size();
      }
    }
  };
  std::vector<std::thread> pool;
  // Runners that measure wall time run one job at a time: concurrent jobs would share the device.
  const int workers = plan.runner().measures_time() && o.run.timing ? 1 : std::max(1, o.jobs);
  for (int i = 0; i < workers; ++i) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);  // the .partial file keeps every finished row for a resume
  plan.finish(overrides, o);
  return sum;
}

const LauncherRegistrar local("local", run_local);

}  // namespace

LauncherRegistrar::LauncherRegistrar(const std::string& name, Launcher launcher) { launchers().add(name, std::move(launcher)); }

std::vector<std::string> launcher_names() { return launchers().names(); }

SweepSummary run_sweep(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  const Launcher* launcher = launchers().find(o.launcher);
  if (!launcher) throw InputError("--launcher: unknown launcher '" + o.launcher + "' (known: " + launchers().known() + ")");
  return (*launcher)(m, overrides, o);
}

}  // namespace semlb::experiments
