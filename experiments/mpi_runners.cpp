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
#include "engine/decomposition/decomposition.hpp"
#include "engine/model/scene.hpp"
#include "engine/run/driver.hpp"
#include "runner.hpp"

namespace semlb::experiments {
namespace {

namespace fs = std::filesystem;

// The scene settings (engine::scene_settings()) these runners take by name.
const std::vector<std::string> kSceneNames = {"cells", "steps", "policy", "initial", "backend", "rebalance_every", "timing"};

std::string get(const Job& job, const std::string& key, const std::string& fallback) {
  const Setting* s = job.find(key);
  return s ? s->value : fallback;
}

std::string scene_path(const Job& job, const RunOptions& o) {
  const std::string scene = get(job, "scene", "");
  return fs::path(scene).is_absolute() ? scene : o.base_dir + "/" + scene;
}

// The row's policy (its scene.decomposition.policy, else `policy`, else the scene file's, else the engine's
// default) and where an error about it points.
std::pair<std::string, std::string> row_policy(const Job& job, const std::string& manifest, const RunOptions& o) {
  for (const char* k : {"scene.decomposition.policy", "policy"})  // scene.KEY overrides come last, so win
    if (const Setting* s = job.find(k)) return {s->value, where_of(*s, manifest, k)};
  engine::Scene scene;
  try {
    scene = engine::load_scene(scene_path(job, o), scene_overrides(job, kSceneNames, manifest));
  } catch (const InputError& e) {
    throw InputError(where_of(*job.find("scene"), manifest, "scene") + e.what());
  }
  return {scene.decomposition->text("policy", engine::Decomposition{}.policy), scene.decomposition->where("policy")};
}

// Refuses, before anything runs: an unknown setting, a missing scene or rank count, a value of the wrong type,
// a bad POLICY.KEY parameter, and a row whose policy the engine cannot run (PolicyNeeds::true_work).
void check_job(const Job& job, const std::string& manifest, const RunOptions& o) {
  for (const auto& [k, s] : job.settings)
    if (k != "scene" && k != "ranks" && std::find(kSceneNames.begin(), kSceneNames.end(), k) == kSceneNames.end() &&
        k.rfind("scene.", 0) != 0 && !is_policy_param(k))
      throw InputError(where_of(s, manifest, k) + "unknown setting for this runner");
  for (const char* k : {"scene", "ranks"})
    if (!job.find(k)) throw InputError(where(manifest, 0, k) + "missing");
  job.integer("ranks", 1, 1, 4096, manifest);
  scene_overrides(job, kSceneNames, manifest);  // typed values
  check_policy_params(job, manifest);  // every policy's parameters, also of policies this row does not run
  const auto [policy, at] = row_policy(job, manifest, o);
  try {
    engine::check_engine_policy(policy);
    make_policy(policy, policy_params(job, manifest)[policy]);
  } catch (const InputError& e) {
    throw InputError(at + e.what());
  }
}

// Runs the job under mpirun (or o.mpi_launcher) into a fresh directory; returns it and the launch's wall seconds (start-up
// included). The row's policy gets its POLICY.KEY settings as decomposition.params.KEY (other policies' are
// not passed). Throws with mpirun's output on failure.
std::pair<std::string, double> launch(const Job& job, const RunOptions& o) {
  const std::string scene = scene_path(job, o);
  std::string key;
  for (const auto& [k, s] : job.settings) key += k + "=" + s.value + ";";
  const fs::path dir = (o.scratch_dir.empty() ? fs::temp_directory_path() : fs::path(o.scratch_dir)) / ("semlb_mpi_" + std::to_string(::getpid()) + "_" + std::to_string(std::hash<std::string>{}(key)));
  fs::remove_all(dir);
  std::ostringstream cmd;
  const std::string mpi = o.mpi_launcher.empty() ? std::string(SEMLB_MPIEXEC) + " --oversubscribe -np" : o.mpi_launcher;
  cmd << "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " << mpi << " " << get(job, "ranks", "1") << " " << fs::read_symlink("/proc/self/exe").string() << " sim --quiet --scene " << scene << " --out " << dir.string()
      << " --set backend.threads=1";
  auto overrides = scene_overrides(job, kSceneNames, "");
  const std::string policy = row_policy(job, "", o).first;
  for (const auto& [k, s] : job.settings)
    if (is_policy_param(k) && k.rfind(policy + ".", 0) == 0) overrides.push_back("decomposition.params." + k.substr(policy.size() + 1) + "=" + s.value);
  for (const auto& o : overrides) cmd << " --set " << o;
  cmd << " 2>&1";
  const auto t0 = std::chrono::steady_clock::now();
  FILE* p = popen(cmd.str().c_str(), "r");
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  if (pclose(p) != 0) throw std::runtime_error("MPI launch failed: " + cmd.str() + "\n" + out);
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
    for (const char* f : {"scene.yaml", "run.csv", engine::rank_times::kFile, "trace.jsonl"})
      if (fs::exists(fs::path(dir) / f)) fs::copy_file(fs::path(dir) / f, to / f, fs::copy_options::overwrite_existing);
  }
  fs::remove_all(dir);
}

// The rows of a CSV our sim wrote, by column name; std::runtime_error naming the file when one of `columns`
// is not in its header.
template <class Names>
std::vector<std::map<std::string, std::string>> csv(const std::string& path, const Names& columns) {
  const auto lines = split(read_file(path), '\n');
  std::vector<std::map<std::string, std::string>> rows;
  const auto header = split(lines[0], ',');
  for (const auto& c : columns)
    if (std::find(header.begin(), header.end(), c) == header.end())
      throw std::runtime_error(path + ": no column '" + std::string(c) + "' in its header '" + lines[0] + "'");
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
  int mpi_ranks(const Job& job) const override { return static_cast<int>(job.integer("ranks", 1, 1, 4096, "")); }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override { check_job(job, manifest, o); }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    namespace rt = engine::rank_times;
    const auto [dir, total] = launch(job, o);
    const std::string run_csv = dir + "/run.csv", rank_csv = dir + "/" + rt::kFile;  // written by our sim
    const auto log = csv(run_csv, std::vector<std::string>{"elements", "wall_s"});
    double wall = 0;  // the time-stepping loop: run.csv holds each log interval's wall seconds
    for (const auto& r : log) wall += parse_real(r.at("wall_s"), run_csv + ": wall_s: ");
    std::map<std::string, double> slowest;  // per interval: the slowest rank's computation time
    double imbalance = 0;
    long moved = 0;
    std::set<std::string> events;
    for (const auto& r : csv(rank_csv, rt::kColumns)) {
      const std::string& step = r.at(rt::kStep);
      slowest[step] = std::max(slowest[step], parse_real(r.at(rt::kComputeS), rank_csv + ": " + rt::kComputeS + ": "));
      if (events.insert(step).second) {
        imbalance += parse_real(r.at(rt::kImbalance), rank_csv + ": " + rt::kImbalance + ": ");
        moved += parse_integer(r.at(rt::kMovedSlices), rank_csv + ": " + rt::kMovedSlices + ": ");
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
  // rank_times.csv's columns of the same names (engine::rank_times), less the exchange and migration times.
  std::vector<std::string> columns() const override {
    namespace rt = engine::rank_times;
    return {rt::kStep, rt::kRank, rt::kComputeS, rt::kImbalance, rt::kMovedSlices};
  }
  bool measures_time() const override { return true; }
  int mpi_ranks(const Job& job) const override { return static_cast<int>(job.integer("ranks", 1, 1, 4096, "")); }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override { check_job(job, manifest, o); }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    namespace rt = engine::rank_times;
    const std::string dir = launch(job, o).first;
    std::vector<std::vector<std::string>> rows;
    for (const auto& r : csv(dir + "/" + rt::kFile, rt::kColumns)) {
      std::vector<std::string> row;
      for (const auto& c : columns()) row.push_back(c == rt::kComputeS && !o.timing ? "0" : r.at(c));
      rows.push_back(std::move(row));
    }
    finish_run(job, o, dir);
    return rows;
  }
};

const RunnerRegistrar sim("mpi_sim", [] { return std::make_unique<MpiSimRunner>(); });
const RunnerRegistrar intervals("mpi_intervals", [] { return std::make_unique<MpiIntervalsRunner>(); });

}  // namespace
}  // namespace semlb::experiments
