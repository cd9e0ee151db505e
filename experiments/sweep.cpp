// Sweep execution: expansion, validation, resume from the .partial file, worker threads, progress line.
#include "sweep.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include <yaml-cpp/yaml.h>

#include "common/digest.hpp"
#include "common/cleanup.hpp"
#include "common/dir_lock.hpp"
#include "common/process.hpp"
#include "common/errors.hpp"
#include "common/progress_line.hpp"
#include "common/registry.hpp"
#include "common/text_io.hpp"
#include "common/version.hpp"
#include "controllers/gru.hpp"

namespace semlb::experiments {
namespace fs = std::filesystem;
namespace {

std::string csv_line(const std::vector<std::string>& cells) { return join(cells) + "\n"; }

// A job's value of axis A; empty when the job's axis group lacks A.
std::string axis_value(const Job& j, const std::string& a) { return j.text(a, ""); }

class Appender {  // one write(2) per row with O_APPEND: a kill leaves whole rows or a torn last line
 public:
  explicit Appender(const std::string& path)
      : path_(path), fd_(::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT, 0644)) {
    if (fd_ < 0) throw std::runtime_error(path + ": cannot open for appending: " + std::strerror(errno));
  }
  ~Appender() { ::close(fd_); }
  void append(const std::string& line) {
    if (::write(fd_, line.data(), line.size()) != static_cast<ssize_t>(line.size()))
      throw std::runtime_error(path_ + ": write failed: " + std::strerror(errno ? errno : ENOSPC));
  }

 private:
  std::string path_;
  int fd_;
};

const char* const kDigestColumn = "settings_digest";  // OUTPUT.partial's first column (docs/experiments.md "Resume")

using FileDigests = std::map<std::string, std::string>;  // path -> digest of its contents ("" when not a file)

// The digest of FILE's contents when it is a regular file ("" otherwise), and, for a YAML file (a scene, a config),
// of the files it names relative to its folder (a scene's tissue.file, a policy's weights; one level deep).
// Each file is read once per sweep (CACHE).
const std::string& file_digest(const fs::path& file, FileDigests& cache, bool follow = true) {
  const std::string key = file.string() + (follow ? "" : "\x1f");
  if (const auto it = cache.find(key); it != cache.end()) return it->second;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return cache[key] = "";
  Digest d;
  d.add(read_file(file.string()));
  if (follow && (file.extension() == ".yaml" || file.extension() == ".yml")) {
    YAML::Node root;
    try {
      root = YAML::LoadFile(file.string());
    } catch (const std::exception&) {
    }  // not YAML: its contents are in the digest already
    std::function<void(const YAML::Node&)> walk = [&](const YAML::Node& n) {
      if (n.IsScalar()) {
        const std::string& v = n.Scalar();
        if (!v.empty() && v.size() < 4096 && v.find('\n') == std::string::npos) {
          const fs::path p = fs::path(v).is_absolute() ? fs::path(v) : file.parent_path() / v;
          if (const std::string& f = file_digest(p, cache, false); !f.empty()) d.add(v).add(f);
        }
      } else if (n.IsSequence() || n.IsMap()) {
        for (const auto& c : n) walk(n.IsMap() ? c.second : c);
      }
    };
    walk(root);
  }
  return cache[key] = d.hex();
}

// The settings digest of a job (docs/experiments.md "Resume"): FNV-1a 64 over the semlb version, the runner,
// whether wall times are measured, every setting of the job (from the manifest, its profile and --set) and the
// contents of every file a setting names (relative to the manifest's folder: a scene, a config, and the files a
// scene names in turn: tissue.file, a policy's weights; POLICY.weights as the policy finds it) and of the shipped
// GRU weights.
std::string settings_digest(const Job& job, const std::string& runner, const RunOptions& o, FileDigests& cache) {
  Digest d;
  d.add(version_string()).add(runner).add(o.timing ? "timing" : "no-timing");
  for (const auto& [k, s] : job.settings) {
    d.add(k).add(s.value);
    if (s.value.empty() || s.value.size() >= 4096 || s.value.find('\n') != std::string::npos) continue;
    // A policy's weights as the policy finds them (the working directory, then the shipped folder); any other
    // file relative to the manifest's folder.
    const bool weights = k.size() >= 7 && k.compare(k.size() - 7, 7, "weights") == 0;
    d.add(file_digest(weights ? fs::path(resolve_gru_weights(s.value)) : fs::path(o.resolve(s.value)), cache));
  }
  d.add(file_digest(default_gru_weights_path(), cache));
  return d.hex();
}

void copy_manifest(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o,
                   const std::string& csv) {
  std::string body, head = "# " + o.command_line + "\n";
  if (!m.path.empty()) {
    body = read_file(m.path);
    std::vector<std::string> argv = {"semlb", "sweep", m.path};  // quoted for /bin/sh: copy-paste reruns it
    if (!m.profile.empty()) argv.insert(argv.end(), {"--profile", m.profile});
    for (const auto& s : overrides) argv.insert(argv.end(), {"--set", s});
    head = "# " + shell_words(argv) + "\n";
  }
  head += "# git revision: " + o.git_revision + "\n# semlb " + version_string() + "\n";
  write_file_atomically(fs::path(csv).replace_extension(".manifest.yaml").string(), head + body);
}

// The sweep's progress on stderr (a ProgressLine): a line at the start, one per finished job (every 5% of them when
// stderr is not a terminal), and a heartbeat for jobs that run long: a job still running 2 s after it started is named
// with its axes, then every 30 s while it runs (`[name] job 3/40 (policy=gru ranks=8) running  12.0 s`).
class Progress {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr double kFirstBeat = 2.0, kEveryBeat = 30.0;  // s

  Progress(std::string name, size_t total, size_t resumed, bool on)
      : name_(std::move(name)), total_(total), done_(resumed), resumed_(resumed), line_(on), start_(Clock::now()) {
    if (!line_.on()) return;
    // A line at once, so a sweep whose first job runs long says it started (then one per finished job)
    line_.show(format_text("[%s] %zu/%zu jobs (%zu resumed)  starting", name_.c_str(), done_, total_, resumed_));
    beat_ = std::thread([this] { heartbeat(); });
  }
  ~Progress() {
    {
      std::lock_guard lock(mu_);
      stop_ = true;
    }
    wake_.notify_all();
    if (beat_.joinable()) beat_.join();
  }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// A job begins: `index` is its 0-based position in the manifest, `label` its axes as `KEY=VALUE ...`.
  void begin(size_t index, std::string label) {
    std::lock_guard lock(mu_);
    running_[index] = Running{std::move(label), Clock::now(), 0};
  }
  /// The job that began with `index` has finished; prints the finished-jobs line.
  void tick(size_t index) {
    std::lock_guard lock(mu_);
    running_.erase(index);
    ++done_;
    if (!line_.on()) return;
    const size_t ran = done_ - resumed_, step = std::max<size_t>(1, (total_ - resumed_) / 20);
    if (!line_.tty() && ran % step != 0 && done_ != total_) return;
    const double s = seconds(start_),
                 eta = eta_seconds(s, static_cast<double>(ran), static_cast<double>(total_ - done_));
    line_.show(format_text("[%s] %zu/%zu jobs (%zu resumed)  %.1f s  ETA %.1f s", name_.c_str(), done_, total_,
                           resumed_, s, eta),
               done_ == total_);
  }

 private:
  struct Running {
    std::string label;
    Clock::time_point since;
    int beats;  // heartbeat lines printed for this job
  };
  static double seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

  void heartbeat() {
    std::unique_lock lock(mu_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stop_; })) {
      for (auto& [index, job] : running_) {
        const double s = seconds(job.since);
        if (s < kFirstBeat + kEveryBeat * job.beats) continue;
        ++job.beats;
        line_.show(format_text("[%s] job %zu/%zu (%s) running  %.1f s", name_.c_str(), index + 1, total_,
                               job.label.c_str(), s),
                   true);
      }
    }
  }

  std::string name_;
  size_t total_, done_, resumed_;
  ProgressLine line_;
  Clock::time_point start_;
  std::mutex mu_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::map<size_t, Running> running_;
  std::thread beat_;
};

long kill_after_rows() {  // test hook: SEMLB_SWEEP_KILL_AFTER=N sends SIGKILL to itself after N new rows
  const char* v = std::getenv("SEMLB_SWEEP_KILL_AFTER");
  return v ? std::atol(v) : -1;
}

long job_delay_ms() {  // test hook: SEMLB_SWEEP_JOB_DELAY_MS=N makes every job last N ms longer (heartbeat tests)
  const char* v = std::getenv("SEMLB_SWEEP_JOB_DELAY_MS");
  return v ? std::atol(v) : 0;
}

}  // namespace

SweepPlan::SweepPlan(const Manifest& m, const SweepOptions& o, Partial partial)
    : m_(m), runner_(make_runner(m.runner, m.path)), jobs_(m.expand()), run_(o.run) {
  // Relative paths in the manifest are relative to its folder, whatever the working directory.
  if (run_.base_dir.empty() && !m.path.empty()) run_.base_dir = fs::absolute(m.path).parent_path().string();
  for (const auto& j : jobs_) runner_->check(j, m.path, run_);
  FileDigests files;
  for (const auto& j : jobs_) digests_.push_back(settings_digest(j, m.runner, run_, files));
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
    if (fs::exists(partial_) && !o.fresh) done_ = current(read_rows(partial_, order), nullptr);
    return;
  }
  // One writer per results folder: locked before anything is written (docs/experiments.md "Locks").
  lock_ = std::make_unique<DirLock>(fs::path(csv_).parent_path().string(), o.wait);
  if (o.fresh) fs::remove(partial_);
  // Only an interrupted run (.partial) is resumed; a finished OUTPUT is always recomputed, since the code
  // that produced it may have changed since.
  if (!fs::exists(partial_)) write_file_atomically(partial_, partial_header());
  size_t stale = 0;
  const auto found = read_rows(partial_, order);
  done_ = current(found, &stale);
  if (stale > 0)
    std::fprintf(stderr,
                 "[%s] recomputing %zu of the %zu finished jobs in %s: made with other settings (their settings digest "
                 "differs: a manifest, profile or --set value, an input file or the semlb build changed)\n",
                 m.name.c_str(), stale, found.size(), partial_.c_str());
  std::string text = partial_header();  // without a torn last line or stale rows, so that appends start on a fresh line
  for (auto& k : order)
    if (done_.count(k)) text += done_[k];
  write_file_atomically(partial_, text);
}

SweepPlan::~SweepPlan() = default;

std::map<std::string, std::string> SweepPlan::current(const std::map<std::string, Rows>& found, size_t* stale) const {
  std::map<std::string, std::string> done;
  for (size_t i = 0; i < jobs_.size(); ++i) {
    const auto it = found.find(key(i));
    if (it == found.end()) continue;
    if (it->second.digest == digests_[i])
      done[key(i)] = it->second.lines;
    else if (stale)
      ++*stale;
  }
  return done;
}

std::string SweepPlan::partial_header() const { return std::string(kDigestColumn) + "," + header(); }

std::string SweepPlan::header() const { return csv_line(layout_.header); }

std::string SweepPlan::key(size_t i) const {
  std::string k;
  for (const auto& a : layout_.axes) k += axis_value(jobs_[i], a) + '\x1f';
  return k;
}

std::string SweepPlan::label(size_t i) const {
  std::string k;
  for (const auto& a : layout_.axes) {  // the axes this job sets (an axis group leaves the others' cells empty)
    const std::string v = axis_value(jobs_[i], a);
    if (!v.empty()) k += (k.empty() ? "" : " ") + a + "=" + v;
  }
  return k;
}

bool SweepPlan::done(size_t i) const { return done_.count(key(i)) > 0; }

// Reads finished rows (job key -> its settings digest and lines) from an OUTPUT.partial or part file; a torn last
// line (no newline) is dropped. A job's rows are appended in one write, so a job is either complete or (torn line
// aside) absent. A file of a semlb without digests (the plain header) reads with empty digests: every row stale.
std::map<std::string, SweepPlan::Rows> SweepPlan::read_rows(const std::string& path,
                                                            std::vector<std::string>& order) const {
  std::map<std::string, Rows> rows;
  std::string text = read_file(path);
  if (text.empty()) return rows;
  if (text.back() != '\n') text.erase(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  std::stringstream ss(text);
  std::string line;
  std::getline(ss, line);
  const bool digests = partial_header() == line + "\n";
  if (!digests && header() != line + "\n")
    throw InputError(path + ":1: header differs from this manifest's columns; move the file away to start afresh");
  long n = 1;
  while (std::getline(ss, line)) {
    ++n;
    auto cells = split(line, ',');
    std::string digest;
    if (digests) {
      digest = cells.front();
      cells.erase(cells.begin());
    }
    if (cells.size() != layout_.header.size())
      throw InputError(where(path, n, "") + "row has the wrong number of columns");
    std::string key;
    for (const auto& a : layout_.axes)
      key += cells[std::find(layout_.header.begin(), layout_.header.end(), a) - layout_.header.begin()] + '\x1f';
    if (!rows.count(key)) order.push_back(key);
    Rows& r = rows[key];
    if (!r.lines.empty() && r.digest != digest)
      r.digest = "mixed";  // never matches: the job reruns
    else
      r.digest = digest;
    r.lines += (digests ? digest + "," : std::string(",")) + join(cells) + "\n";  // a job may have several rows
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
                                ? job.find(columns[c])
                                : nullptr;
      cells.push_back(axis ? axis->value : row[c]);
    }
    lines += digests_[i] + "," + csv_line(cells);
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
    throw InputError(path + ": rows are not job " + std::to_string(i) +
                     "'s of this manifest; remove the file to rerun the job");
  if (rows[order[0]].digest != digests_[i])
    throw InputError(path + ": job " + std::to_string(i) +
                     "'s rows were made with other settings (settings digest); remove the file to rerun the job");
  return rows[order[0]].lines;
}

void SweepPlan::finish(const std::vector<std::string>& overrides, const SweepOptions& o) const {
  std::string text = header();  // job order, without the digest column; rows of other jobs in .partial are dropped
  for (size_t i = 0; i < jobs_.size(); ++i)
    for (const auto& line : split(done_.at(key(i)), '\n'))
      if (!line.empty()) text += line.substr(line.find(',') + 1) + "\n";
  write_file_atomically(csv_, text);
  fs::remove(partial_);
  copy_manifest(m_, overrides, o, csv_);
}

namespace {

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
  const long kill_after = kill_after_rows(), delay_ms = job_delay_ms();
  auto worker = [&] {
    for (size_t t; (t = next++) < todo.size();) {
      try {
        progress.begin(todo[t], plan.label(todo[t]));
        const std::string lines = plan.rows(todo[t]);  // all rows of the job, appended with one write
        if (delay_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
        std::lock_guard lock(mu);
        plan.record(todo[t], lines);
        ++sum.ran;
        progress.tick(todo[t]);
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

const Registrar<LauncherInfo> local("local", {run_local});

}  // namespace

SweepSummary run_sweep(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  const LauncherInfo* launcher = Launchers::find(o.launcher);
  if (!launcher)
    throw InputError("--launcher: unknown launcher '" + o.launcher + "' (known: " + Launchers::known() + ")");
  // A SIGINT, SIGTERM or SIGHUP of the sweep stops the rows' children (mpiexec and its ranks), removes their run
  // folders and the results folder's lock, then ends the sweep by that signal (docs/experiments.md, "Resume,
  // settings digests and locks").
  const SignalCleanup cleanup;
  return launcher->launch(m, overrides, o);
}

}  // namespace semlb::experiments
