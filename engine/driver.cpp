// The run driver behind `semlb sim`.
#include "driver.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "controllers/text_io.hpp"
#include "distributed.hpp"
#include "io.hpp"
#include "simulation.hpp"
#include "tissue.hpp"

namespace semlb::engine {
namespace {

namespace fs = std::filesystem;

std::string snapshot_name(long step) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "snapshots/step_%09ld.h5", step);
  return buf;
}

// Rows of an earlier run.csv up to `step` (restart continues the same log); the header is rewritten.
std::vector<std::string> earlier_rows(const std::string& path, long step) {
  std::vector<std::string> rows;
  if (!fs::exists(path)) return rows;
  const auto lines = split(read_file(path), '\n');
  for (size_t i = 1; i < lines.size(); ++i)
    if (!lines[i].empty() && std::stol(split(lines[i], ',')[0]) <= step) rows.push_back(lines[i]);
  return rows;
}

std::vector<Snapshot> earlier_snapshots(const std::string& dir, long step) {
  std::vector<Snapshot> out;
  if (!fs::exists(dir + "/snapshots")) return out;
  for (const auto& entry : fs::directory_iterator(dir + "/snapshots")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("step_", 0) != 0 || entry.path().extension() != ".h5") continue;
    const long s = std::stol(name.substr(5, 9));
    if (s > step) continue;
    const State st = read_state(entry.path().string());
    out.push_back({s, st.time, st.elements(), snapshot_name(s)});
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.step < b.step; });
  return out;
}

class StatusLine {
 public:
  StatusLine(bool quiet, long first, long last) : quiet_(quiet), tty_(isatty(2)), first_(first), last_(last) {}
  void update(const State& s, double wall, bool force) {
    if (quiet_ || (!force && wall - shown_ < (tty_ ? 1.0 : 10.0))) return;
    shown_ = wall;
    const double done = static_cast<double>(s.step - first_), left = static_cast<double>(last_ - s.step);
    std::fprintf(stderr, "%sstep %ld/%ld | cells %ld | elements %ld | %.1f s | ETA %.1f s%s", tty_ ? "\r" : "", s.step,
                 last_, s.cells(), s.elements(), wall, done > 0 ? wall / done * left : 0.0, tty_ && !force ? "" : "\n");
  }

 private:
  bool quiet_, tty_;
  long first_, last_;
  double shown_ = -1e9;
};

}  // namespace

RunSummary run_scene(Scene& scene, const RunConfig& config) {
  State initial = config.restart.empty() ? make_tissue(scene) : read_state(config.restart);
  if (!config.restart.empty() && scene.auto_box) fit_box(scene, initial);  // the tissue section is not used
  const long first = initial.step, last = std::max(scene.steps, first);
  Simulation sim(scene, std::move(initial));  // all input checked before anything is written

  const std::string dir = config.out_dir;
  fs::create_directories(dir + "/snapshots");
  write_file_atomically(dir + "/scene.yaml", "# semlb " + config.git_revision + ": " + config.command_line + "\n" + scene.text);
  std::string header = "step,time_h,cells,elements,wall_s";
  for (const auto& p : sim.phases()) header += "," + p + "_s";
  std::vector<std::string> rows = earlier_rows(dir + "/run.csv", first);
  std::vector<Snapshot> snapshots = earlier_snapshots(dir, first);
  const std::map<std::string, std::string> attrs = {{"git_revision", config.git_revision}, {"scene", scene.name},
                                                    {"backend", sim.backend().name()}};

  StatusLine status(config.quiet, first, last);
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  auto next = [&](long every, long step) { return every > 0 ? (step / every + 1) * every : last; };
  std::vector<double> phase_before = sim.phase_seconds();
  double wall_before = 0;
  try {
    while (sim.host_state().step < last) {
      const long step = sim.host_state().step;
      const long stop = std::min({last, next(scene.log_every, step), next(scene.snapshot_every, step), next(scene.checkpoint_every, step)});
      sim.advance(stop);
      const State& s = sim.sync();
      if (stop % scene.log_every == 0 || stop == last) {
        std::ostringstream row;
        const double w = wall();
        row << s.step << "," << s.time << "," << s.cells() << "," << s.elements() << "," << w - wall_before;
        for (size_t p = 0; p < sim.phases().size(); ++p) row << "," << sim.phase_seconds()[p] - phase_before[p];
        rows.push_back(row.str());
        phase_before = sim.phase_seconds();
        wall_before = w;
        std::string csv = header + "\n";
        for (const auto& r : rows) csv += r + "\n";
        write_file_atomically(dir + "/run.csv", csv);
      }
      if (scene.snapshot_every > 0 && stop % scene.snapshot_every == 0) {
        write_state(dir + "/" + snapshot_name(stop), s, attrs);
        snapshots.push_back({stop, s.time, s.elements(), snapshot_name(stop)});
        write_xdmf(dir + "/snapshots.xmf", snapshots);
      }
      if (scene.checkpoint_every > 0 && stop % scene.checkpoint_every == 0) write_state(dir + "/checkpoint.h5", s, attrs);
      status.update(s, wall(), false);
    }
  } catch (const SimulationError&) {
    write_state(dir + "/failure.h5", sim.host_state(), attrs);
    throw;
  }
  const State& s = sim.sync();
  write_state(dir + "/final.h5", s, attrs);
  status.update(s, wall(), true);
  return {s.step - first, s.cells(), s.elements(), wall(), sim.backend().device_name()};
}

RunSummary run_scene_decomposed(Scene& scene, const RunConfig& config, Mpi& mpi) {
  State initial = config.restart.empty() ? make_tissue(scene) : read_state(config.restart);
  if (!config.restart.empty() && scene.auto_box) fit_box(scene, initial);
  scene.backend.local_rank = mpi.local_rank();
  const long first = initial.step, last = std::max(scene.steps, first);
  const std::string dir = config.out_dir;
  const bool root = mpi.rank() == 0;
  DistributedSimulation sim(scene, initial, mpi, root ? dir + "/trace.jsonl" : "");  // all input checked here
  if (root) fs::create_directories(dir + "/snapshots");
  std::vector<Snapshot> snapshots = root ? earlier_snapshots(dir, first) : std::vector<Snapshot>{};
  if (root) write_file_atomically(dir + "/scene.yaml", "# semlb " + config.git_revision + ": " + config.command_line + "\n" + scene.text);
  const std::map<std::string, std::string> attrs = {{"git_revision", config.git_revision}, {"scene", scene.name},
                                                    {"backend", sim.local().backend().name()},
                                                    {"ranks", std::to_string(mpi.size())}};
  StatusLine status(config.quiet || !root, first, last);
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  auto next = [&](long every, long step) { return every > 0 ? (step / every + 1) * every : last; };
  std::string log = "step,time_h,cells,elements,wall_s\n";
  try {
    while (sim.step() < last) {
      const long stop = std::min({last, next(scene.log_every, sim.step()), next(scene.checkpoint_every, sim.step()),
                                  next(scene.snapshot_every, sim.step())});
      sim.advance(stop);
      const State all = sim.gather();
      if (!root) continue;
      std::ostringstream row;
      row << all.step << "," << all.time << "," << all.cells() << "," << all.elements() << "," << wall() << "\n";
      log += row.str();
      write_file_atomically(dir + "/run.csv", log);
      if (scene.snapshot_every > 0 && stop % scene.snapshot_every == 0) {
        write_state(dir + "/" + snapshot_name(stop), all, attrs);
        snapshots.push_back({stop, all.time, all.elements(), snapshot_name(stop)});
        write_xdmf(dir + "/snapshots.xmf", snapshots);
      }
      if (scene.checkpoint_every > 0 && stop % scene.checkpoint_every == 0) write_state(dir + "/checkpoint.h5", all, attrs);
      status.update(all, wall(), false);
    }
  } catch (const SimulationError&) {
    const State all = sim.gather();  // every rank reaches this: the failure was agreed collectively
    if (root) write_state(dir + "/failure.h5", all, attrs);
    throw;
  }
  const State all = sim.gather();
  if (root) {
    write_state(dir + "/final.h5", all, attrs);
    std::string rows = "step,rank,compute_s,imbalance,moved_slices\n";
    for (const auto& iv : sim.intervals())
      for (size_t r = 0; r < iv.times.size(); ++r)
        rows += std::to_string(iv.step) + "," + std::to_string(r) + "," + std::to_string(iv.times[r]) + "," +
                std::to_string(iv.imbalance) + "," + std::to_string(iv.moved) + "\n";
    write_file_atomically(dir + "/rank_times.csv", rows);
    status.update(all, wall(), true);
  }
  return {all.step - first, all.cells(), all.elements(), wall(), sim.local().backend().device_name()};
}

}  // namespace semlb::engine
