// Runners that launch `mpirun -np RANKS semlb sim` (strong_scaling, load_balance: "mpi_sim", one summary row;
// rank_balance: "mpi_intervals", one row per rebalancing interval and rank) and read its outputs.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "runner.hpp"

namespace semlb::experiments {
namespace {

namespace fs = std::filesystem;

const std::set<std::string> kKeys = {"scene", "ranks", "cells", "steps", "policy", "initial", "backend", "rebalance_every"};

std::string get(const Job& job, const std::string& key, const std::string& fallback) {
  const Setting* s = job.find(key);
  return s ? s->value : fallback;
}

void check_job(const Job& job, const std::string& manifest) {
  for (const auto& [k, s] : job.settings)
    if (!kKeys.count(k) && k.rfind("scene.", 0) != 0) throw InputError(where_of(s, manifest, k) + "unknown setting for this runner");
  for (const char* k : {"scene", "ranks"})
    if (!job.find(k)) throw InputError(where(manifest, 0, k) + "missing");
  job.integer("ranks", 1, 1, 4096, manifest);
}

// Runs the job under mpirun into a fresh directory; returns it and the launch's wall seconds (start-up
// included). Throws with mpirun's output on failure.
std::pair<std::string, double> launch(const Job& job, const RunOptions& o) {
  const std::string scene = fs::path(get(job, "scene", "")).is_absolute() ? get(job, "scene", "") : o.base_dir + "/" + get(job, "scene", "");
  std::string key;
  for (const auto& [k, s] : job.settings) key += k + "=" + s.value + ";";
  const fs::path dir = fs::temp_directory_path() / ("semlb_mpi_" + std::to_string(::getpid()) + "_" + std::to_string(std::hash<std::string>{}(key)));
  fs::remove_all(dir);
  std::ostringstream cmd;
  cmd << "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " << SEMLB_MPIEXEC << " --oversubscribe -np " << get(job, "ranks", "1")
      << " " << fs::read_symlink("/proc/self/exe").string() << " sim --quiet --scene " << scene << " --out " << dir.string()
      << " --set backend.threads=1";
  for (const auto& o : scene_overrides(job, {{"cells", "tissue.cells"}, {"steps", "time.steps"}, {"policy", "decomposition.policy"},
                                             {"initial", "decomposition.initial"}, {"backend", "backend.name"},
                                             {"rebalance_every", "decomposition.rebalance_every"}}))
    cmd << " --set " << o;
  cmd << " 2>&1";
  const auto t0 = std::chrono::steady_clock::now();
  FILE* p = popen(cmd.str().c_str(), "r");
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  if (pclose(p) != 0) throw std::runtime_error("mpirun failed: " + cmd.str() + "\n" + out);
  return {dir.string(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

// Removes the run's directory; with --keep-runs its files stay under TRACE_DIR/<its settings, scene left out>/.
void finish_run(const Job& job, const RunOptions& o, const std::string& dir) {
  if (!o.trace_dir.empty()) {
    std::string label;
    for (const auto& [k, s] : job.settings)
      if (k != "scene") label += (label.empty() ? "" : "_") + k + "=" + s.value;
    std::replace(label.begin(), label.end(), '/', '-');
    const fs::path to = fs::path(o.trace_dir) / label;
    fs::create_directories(to);
    for (const char* f : {"run.csv", "rank_times.csv", "trace.jsonl"})
      if (fs::exists(fs::path(dir) / f)) fs::copy_file(fs::path(dir) / f, to / f, fs::copy_options::overwrite_existing);
  }
  fs::remove_all(dir);
}

std::vector<std::map<std::string, std::string>> csv(const std::string& path) {
  const auto lines = split(read_file(path), '\n');
  std::vector<std::map<std::string, std::string>> rows;
  const auto header = split(lines[0], ',');
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const auto f = split(lines[i], ',');
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < header.size() && c < f.size(); ++c) row[header[c]] = f[c];
    rows.push_back(row);
  }
  return rows;
}

class MpiSimRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override {
    return {"elements", "total_s", "wall_s", "compute_s", "mean_imbalance", "migrated_slices", "events"};
  }
  bool measures_time() const override { return true; }
  void check(const Job& job, const std::string& manifest, const RunOptions&) const override { check_job(job, manifest); }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const auto [dir, total] = launch(job, o);
    const auto log = csv(dir + "/run.csv");
    double wall = 0;  // the time-stepping loop: run.csv holds each log interval's wall seconds
    const std::string run_csv = dir + "/run.csv", rank_csv = dir + "/rank_times.csv";  // written by our sim
    for (const auto& r : log) wall += parse_real(r.at("wall_s"), run_csv + ": wall_s: ");
    std::map<std::string, double> slowest;  // per interval: the slowest rank's computation time
    double imbalance = 0;
    long moved = 0;
    std::set<std::string> events;
    for (const auto& r : csv(dir + "/rank_times.csv")) {
      slowest[r.at("step")] = std::max(slowest[r.at("step")], parse_real(r.at("compute_s"), rank_csv + ": compute_s: "));
      if (events.insert(r.at("step")).second) {
        imbalance += parse_real(r.at("imbalance"), rank_csv + ": imbalance: ");
        moved += parse_integer(r.at("moved_slices"), rank_csv + ": moved_slices: ");
      }
    }
    double compute = 0;
    for (const auto& [s, t] : slowest) compute += t;
    finish_run(job, o, dir);
    auto fmt = [&](double v) { return format_real(o.timing ? v : 0.0); };
    return {{log.back().at("elements"), fmt(total), fmt(wall), fmt(compute),
             format_real(events.empty() ? 0.0 : imbalance / static_cast<double>(events.size())), std::to_string(moved),
             std::to_string(events.size())}};
  }
};

class MpiIntervalsRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override { return {"step", "rank", "compute_s", "imbalance", "moved_slices"}; }
  bool measures_time() const override { return true; }
  void check(const Job& job, const std::string& manifest, const RunOptions&) const override { check_job(job, manifest); }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const std::string dir = launch(job, o).first;
    std::vector<std::vector<std::string>> rows;
    for (const auto& r : csv(dir + "/rank_times.csv"))
      rows.push_back({r.at("step"), r.at("rank"), o.timing ? r.at("compute_s") : "0", r.at("imbalance"), r.at("moved_slices")});
    finish_run(job, o, dir);
    return rows;
  }
};

const RunnerRegistrar sim("mpi_sim", [] { return std::make_unique<MpiSimRunner>(); });
const RunnerRegistrar intervals("mpi_intervals", [] { return std::make_unique<MpiIntervalsRunner>(); });

}  // namespace
}  // namespace semlb::experiments
