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
#include "common/text_io.hpp"

namespace semlb::experiments {
namespace fs = std::filesystem;
namespace {

std::string csv_line(const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + cells[i];
  return s + "\n";
}

// The sweep's own key columns (axes the runner does not write) come first, then the runner's columns.
struct Layout {
  std::vector<std::string> header;
  std::vector<std::string> axes;         // resume key, in manifest order
  std::vector<std::string> extra_axes;   // axes not among the runner's columns
};

Layout make_layout(const Manifest& m, const Runner& r) {
  Layout l;
  l.axes = m.axis_names();
  const auto cols = r.columns();
  for (const auto& a : l.axes)
    if (std::find(cols.begin(), cols.end(), a) == cols.end()) l.extra_axes.push_back(a);
  l.header = l.extra_axes;
  l.header.insert(l.header.end(), cols.begin(), cols.end());
  return l;
}

// A job's value of axis A; empty when the job's axis group lacks A.
std::string axis_value(const Job& j, const std::string& a) {
  const Setting* s = j.find(a);
  return s ? s->value : "";
}

std::string key_of(const Job& j, const Layout& l) {
  std::string k;
  for (const auto& a : l.axes) k += axis_value(j, a) + '\x1f';
  return k;
}

std::string key_of_row(const std::vector<std::string>& row, const std::vector<std::string>& header, const Layout& l) {
  std::string k;
  for (const auto& a : l.axes) k += row[std::find(header.begin(), header.end(), a) - header.begin()] + '\x1f';
  return k;
}

// Reads finished rows (job key -> its lines) from an earlier CSV; a torn last line (no newline) is dropped.
// A job's rows are appended in one write, so a job is either complete or (torn line aside) absent.
std::map<std::string, std::string> read_rows(const std::string& path, const Layout& l, std::vector<std::string>& order) {
  std::map<std::string, std::string> rows;
  std::string text = read_file(path);
  if (text.empty()) return rows;
  if (text.back() != '\n') text.erase(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  std::stringstream ss(text);
  std::string line;
  std::getline(ss, line);
  if (csv_line(l.header) != line + "\n")
    throw InputError(path + ":1: header differs from this manifest's columns; move the file away to start afresh");
  long n = 1;
  while (std::getline(ss, line)) {
    ++n;
    const auto cells = split(line, ',');
    if (cells.size() != l.header.size()) throw InputError(where(path, n, "") + "row has the wrong number of columns");
    const auto key = key_of_row(cells, l.header, l);
    if (!rows.count(key)) order.push_back(key);
    rows[key] += line + "\n";  // a job may have several rows
  }
  return rows;
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
        tty_(isatty(fileno(stderr))), start_(std::chrono::steady_clock::now()) {}
  void tick() {
    ++done_;
    if (!on_) return;
    const size_t ran = done_ - resumed_, step = std::max<size_t>(1, (total_ - resumed_) / 20);
    if (!tty_ && ran % step != 0 && done_ != total_) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double eta = ran ? s / ran * (total_ - done_) : 0.0;
    std::fprintf(stderr, "%s[%s] %zu/%zu rows (%zu resumed)  %.1f s  ETA %.1f s%s", tty_ ? "\r" : "", name_.c_str(),
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

SweepSummary run_sweep(const Manifest& m, const std::vector<std::string>& overrides, const SweepOptions& o) {
  const auto runner = make_runner(m.runner, m.path);
  const auto jobs = m.expand();
  RunOptions run = o.run;
  if (run.base_dir.empty() && !m.path.empty()) run.base_dir = fs::path(m.path).parent_path().string();
  for (const auto& j : jobs) runner->check(j, m.path, run);
  const Layout layout = make_layout(m, *runner);

  SweepSummary sum;
  sum.csv_path = (fs::path(o.results_dir) / m.output).string();
  const std::string partial = sum.csv_path + ".partial";
  fs::create_directories(fs::path(sum.csv_path).parent_path());
  if (o.fresh) fs::remove(partial);
  // Only an interrupted run (.partial) is resumed; a finished OUTPUT is always recomputed, since the code
  // that produced it may have changed since.
  if (!fs::exists(partial)) write_file_atomically(partial, csv_line(layout.header));
  std::vector<std::string> order;
  auto done = read_rows(partial, layout, order);
  write_file_atomically(partial, [&] { std::string s = csv_line(layout.header); for (auto& k : order) s += done[k]; return s; }());

  std::vector<size_t> todo;
  for (size_t i = 0; i < jobs.size(); ++i)
    if (!done.count(key_of(jobs[i], layout))) todo.push_back(i);
  sum.rows = jobs.size();
  sum.resumed = jobs.size() - todo.size();

  Appender out(partial);
  Progress progress(m.name, jobs.size(), sum.resumed, o.progress);
  std::mutex mu;
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  const long kill_after = kill_after_rows();
  const auto columns = runner->columns();
  auto worker = [&] {
    for (size_t t; (t = next++) < todo.size();) {
      const Job& job = jobs[todo[t]];
      try {
        std::string line;  // all rows of the job, appended with one write
        for (const auto& row : runner->run(job, run)) {
          std::vector<std::string> cells;
          for (const auto& a : layout.extra_axes) cells.push_back(axis_value(job, a));
          for (size_t c = 0; c < row.size(); ++c) {  // key columns keep the manifest's spelling
            const Setting* axis = std::find(layout.axes.begin(), layout.axes.end(), columns[c]) != layout.axes.end()
                                      ? job.find(columns[c]) : nullptr;
            cells.push_back(axis ? axis->value : row[c]);
          }
          line += csv_line(cells);
        }
        std::lock_guard lock(mu);
        out.append(line);
        done[key_of(job, layout)] = line;
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
  const int workers = runner->measures_time() && o.run.timing ? 1 : std::max(1, o.jobs);
  for (int i = 0; i < workers; ++i) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);  // the .partial file keeps every finished row for a resume

  std::string final_text = csv_line(layout.header);  // job order; rows of other jobs in .partial are dropped
  for (const auto& j : jobs) final_text += done[key_of(j, layout)];
  write_file_atomically(sum.csv_path, final_text);
  fs::remove(partial);
  copy_manifest(m, overrides, o, sum.csv_path);
  return sum;
}

}  // namespace semlb::experiments
