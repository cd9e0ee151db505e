// The run driver behind `semlb sim`.
#include "driver.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>

#include "common/dir_lock.hpp"
#include "common/errors.hpp"
#include "common/process.hpp"
#include "common/progress_line.hpp"
#include "common/text_io.hpp"
#include "decomposition/distributed.hpp"
#include "io/io.hpp"
#include "simulation/simulation.hpp"
#include "model/tissue.hpp"

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
    if (!lines[i].empty() &&
        parse_integer(split(lines[i], ',')[0], semlb::where(path, static_cast<long>(i) + 1, "step")) <= step)
      rows.push_back(lines[i]);
  return rows;
}

std::vector<Snapshot> earlier_snapshots(const std::string& dir, long step) {
  std::vector<Snapshot> out;
  if (!fs::exists(dir + "/snapshots")) return out;
  for (const auto& entry : fs::directory_iterator(dir + "/snapshots")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("step_", 0) != 0 || entry.path().extension() != ".h5") continue;
    if (name.size() != 17 || name.substr(5, 9).find_first_not_of("0123456789") != std::string::npos)
      continue;                                   // step_NNNNNNNNN.h5
    const long s = std::stol(name.substr(5, 9));  // nine digits, zero-padded by snapshot_name()
    if (s > step) continue;
    const State st = read_state(entry.path().string());
    out.push_back({s, st.time, st.elements(), snapshot_name(s)});
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.step < b.step; });
  return out;
}

class StatusLine {
 public:
  StatusLine(bool quiet, long first, long last) : line_(!quiet), first_(first), last_(last) {}
  void update(long step, long cells, long elements, double wall, bool force) {
    if (!line_.on() || (!force && wall - shown_ < (line_.tty() ? 1.0 : 10.0))) return;
    if (force && !line_.tty() && step == shown_step_) return;  // a log has this state's line already
    shown_ = wall;
    shown_step_ = step;
    const double eta = eta_seconds(wall, static_cast<double>(step - first_), static_cast<double>(last_ - step));
    line_.show(format_text("step %ld/%ld | cells %ld | elements %ld | %.1f s | ETA %.1f s", step, last_, cells,
                           elements, wall, eta),
               force);
  }

 private:
  ProgressLine line_;  // common/progress_line.hpp: the terminal/log behaviour of every status line
  long first_, last_, shown_step_ = -1;
  double shown_ = -1e9;
};

// The files every run writes into DIR: scene.yaml, run.csv (earlier rows kept on restart), snapshots (the
// first state's included) with their XDMF index snapshots.xmf, and checkpoint.h5, final.h5 and failure.h5,
// each with its own index (checkpoint.xmf, final.xmf, failure.xmf).
class RunOutputs {
 public:
  RunOutputs(const Scene& scene, const RunConfig& config, long first, std::string header,
             std::map<std::string, std::string> attrs)
      : lock_(config.out_dir, config.wait),
        scene_(scene),
        dir_(config.out_dir),
        header_(std::move(header)),
        attrs_(std::move(attrs)) {
    write_file_atomically(dir_ + "/scene.yaml",
                          "# semlb " + config.git_revision + ": " + config.command_line + "\n" + scene.text);
    rows_ = earlier_rows(dir_ + "/run.csv", first);
    snapshots_ = earlier_snapshots(dir_, first);
    if (!scene.write_final)  // output.final: false: no final state in DIR, not even an earlier run's
      for (const char* f : {"/final.h5", "/final.xmf"}) fs::remove(dir_ + f);
  }
  void log(const std::string& row) {
    rows_.push_back(row);
    std::string csv = header_ + "\n";
    for (const auto& r : rows_) csv += r + "\n";
    write_file_atomically(dir_ + "/run.csv", csv);
  }
  bool wants_state(long step) const { return due(scene_.snapshot_every, step) || due(scene_.checkpoint_every, step); }
  // Whether the run's first state (step 0, or a restart's step) needs a snapshot: due and not already written.
  bool wants_first_snapshot(long step) const {
    return due(scene_.snapshot_every, step) &&
           std::none_of(snapshots_.begin(), snapshots_.end(), [&](const Snapshot& s) { return s.step == step; });
  }
  // The snapshot of the run's first state, if wants_first_snapshot (no checkpoint: the run starts from it).
  void save_first(const State& s) {
    if (wants_first_snapshot(s.step)) snapshot(s);
  }
  // The snapshot and checkpoint due at s.step; a decomposed run's checkpoint also holds its balancer.
  void save(const State& s, const DecompositionCheckpoint* decomposition = nullptr) {
    if (due(scene_.snapshot_every, s.step)) snapshot(s);
    if (due(scene_.checkpoint_every, s.step)) write("checkpoint.h5", s, decomposition);
  }
  // DIR/NAME.h5 and its XDMF index DIR/NAME.xmf (a temporal collection of one).
  void write(const std::string& name, const State& s, const DecompositionCheckpoint* decomposition = nullptr) const {
    write_state(dir_ + "/" + name, s, attrs_, decomposition);
    write_xdmf(dir_ + "/" + fs::path(name).stem().string() + ".xmf", {{s.step, s.time, s.elements(), name}});
  }
  const std::string& dir() const { return dir_; }

 private:
  static bool due(long every, long step) { return every > 0 && step % every == 0; }
  void snapshot(const State& s) {
    fs::create_directories(dir_ + "/snapshots");
    write_state(dir_ + "/" + snapshot_name(s.step), s, attrs_);
    snapshots_.push_back({s.step, s.time, s.elements(), snapshot_name(s.step)});
    write_xdmf(dir_ + "/snapshots.xmf", snapshots_);
  }
  DirLock lock_;  // one run writes DIR at a time; taken (and DIR created) before any file is written
  const Scene& scene_;
  std::string dir_, header_;
  std::map<std::string, std::string> attrs_;
  std::vector<std::string> rows_;
  std::vector<Snapshot> snapshots_;
};

// The state written on a numerical failure: frozen since the failing step (its positions as that step's
// moves left them), labelled with that step.
State failing_state(State s, long step, double dt) {
  if (step >= 0) {
    s.step = step;
    s.time = static_cast<double>(step) * dt;
  }
  return s;
}

// A state read from a file (a restart, tissue.file) at or past the run's last step would run nothing: refused,
// naming both steps, as LAMMPS refuses `run N upto` before the current step. A generated tissue at step 0 with
// time.steps 0 is a run of its first state alone (its files written), and allowed.
void check_steps_ahead(const Scene& scene, const RunConfig& config, const State& initial) {
  if (scene.steps > initial.step || (config.restart.empty() && initial.step == 0)) return;
  const std::string from = config.restart.empty() ? "the tissue.file state" : config.restart;
  throw InputError("--steps / time.steps: step " + std::to_string(scene.steps) + " is not after step " +
                   std::to_string(initial.step) + " of " + from + ": nothing to run (give a final step after " +
                   std::to_string(initial.step) + ")");
}

// The next step at which the driver must stop to log or write a file.
long next_stop(const Scene& scene, long step, long last) {
  auto next = [&](long every) { return every > 0 ? (step / every + 1) * every : last; };
  return std::min({last, next(scene.log_every), next(scene.snapshot_every), next(scene.checkpoint_every)});
}

// What the one run loop (drive) needs of a run: one device (OneDevice) or this rank of a decomposed run
// (Decomposed). The collective calls (since_last, any, whole, agreed) are called on every rank alike.
class Run {
 public:
  virtual ~Run() = default;
  virtual bool root() const = 0;
  virtual long step() = 0;
  virtual void advance(long stop) = 0;
  virtual std::pair<long, long> totals() = 0;  // cells and elements (over every rank)
  // Per phase the seconds since the last call (decomposed: the slowest rank's), then the bytes h2d and d2h (summed).
  virtual std::pair<std::vector<double>, std::array<long, 2>> since_last() = 0;
  virtual void mark() = 0;          // since_last counts from now (this rank's own baseline; not collective)
  virtual bool any(bool mine) = 0;  // true when `mine` is true on some rank
  // The whole tissue (decomposed: gathered on rank 0, empty elsewhere), valid until the next call: no copy of a
  // one-device state.
  virtual const State& whole() = 0;
  virtual void agreed(const std::function<void()>& f) = 0;              // f, whose errors every rank agrees on
  virtual void save(RunOutputs& out, const State& all, long stop) = 0;  // the snapshot/checkpoint due at `stop`
  // The state to write as failure.h5 when `e` (thrown by advance) is a numerical failure; false to rethrow as is.
  virtual bool failed(const std::exception& e, State& frozen) = 0;
  virtual void finish(RunOutputs& out, const State& all) = 0;  // files beside final.h5 (rank 0)
  virtual std::string device() = 0;
  // Collective: sum.ranks, sum.phases (each phase's seconds over the run, min / avg / max over the ranks) and the
  // neighbour list's builds (RunSummary).
  virtual void breakdown(RunSummary& sum) = 0;
};

// min / avg / max over ranks of per-rank values.
PhaseSpread spread_of(const std::string& name, const std::vector<double>& per_rank) {
  PhaseSpread p{name, per_rank.empty() ? 0.0 : per_rank[0], 0.0, 0.0};
  for (double v : per_rank) {
    p.min = std::min(p.min, v);
    p.max = std::max(p.max, v);
    p.avg += v / static_cast<double>(per_rank.size());
  }
  return p;
}

// The loop every `semlb sim` runs, once: stops at each log/snapshot/checkpoint step, one run.csv row per log step
// (the header: step,time_h,cells,elements,wall_s, a column per phase, bytes_h2d,bytes_d2h), the status line, the
// failure state, final.h5. `out` is rank 0's files (null elsewhere).
RunSummary drive(Run& run, const Scene& scene, const RunConfig& config, long first, RunOutputs* out) {
  const long last = std::max(scene.steps, first);
  const bool root = run.root();
  StatusLine status(config.quiet || !root, first, last);
  const auto t0 = std::chrono::steady_clock::now();
  const double started = process_seconds();
  double wall_before = 0;
  if (run.any(root && out->wants_first_snapshot(first))) {
    const State& all = run.whole();
    run.agreed([&] {
      if (root) out->save_first(all);
    });
  }
  run.mark();        // the first row's bytes are its steps', not the first snapshot's download
  const State none;  // what `all` is at a stop that writes no state
  double element_steps = 0, output_seconds = 0;
  try {
    while (run.step() < last) {
      const long stop = next_stop(scene, run.step(), last), from = run.step();
      run.advance(stop);
      const auto [cells, elements] = run.totals();  // no download: the state crosses only when a file needs it
      element_steps += static_cast<double>(elements) * static_cast<double>(stop - from);
      const bool log = stop % scene.log_every == 0 || stop == last;
      std::pair<std::vector<double>, std::array<long, 2>> since;
      if (log) since = run.since_last();
      const bool gather = run.any(root && out->wants_state(stop));
      const State& all = gather ? run.whole() : none;
      run.agreed([&] {
        if (!root) return;
        const auto written = std::chrono::steady_clock::now();
        if (log) {
          std::ostringstream row;
          const double w = seconds_since(t0);
          row << stop << "," << format_real(static_cast<double>(stop) * scene.dt) << "," << cells << "," << elements
              << "," << format_real(w - wall_before);
          for (double t : since.first) row << "," << format_real(t);
          row << "," << since.second[0] << "," << since.second[1];
          out->log(row.str());
          wall_before = w;
        }
        if (gather) run.save(*out, all, stop);
        output_seconds += seconds_since(written);
      });
      status.update(stop, cells, elements, seconds_since(t0), false);
    }
  } catch (const std::exception& e) {
    State frozen;
    if (!run.failed(e, frozen)) throw;
    run.agreed([&] {
      if (root) out->write("failure.h5", frozen);
    });
    throw;
  }
  const double loop_seconds = seconds_since(t0);
  // output.final: false leaves the state on the device(s): no download, no gather, no file
  const State& all = scene.write_final ? run.whole() : none;
  const auto [cells, elements] = scene.write_final ? std::pair{all.cells(), all.elements()} : run.totals();
  run.agreed([&] {
    if (!root) return;
    if (scene.write_final) out->write("final.h5", all);
    run.finish(*out, all);
    status.update(run.step(), cells, elements, seconds_since(t0), true);
  });
  RunSummary sum;
  sum.steps = run.step() - first;
  sum.cells = cells;
  sum.elements = elements;
  sum.wrote_final = scene.write_final;
  sum.device = run.device();
  sum.loop_seconds = loop_seconds;
  sum.start_seconds = started;
  sum.closing_seconds = seconds_since(t0) - loop_seconds;
  sum.element_steps = element_steps;
  sum.output_seconds = output_seconds;
  run.breakdown(sum);
  return sum;
}

// The header of run.csv for these phases.
std::string run_header(const std::vector<std::string>& phases) {
  std::string header = "step,time_h,cells,elements,wall_s";
  for (const auto& p : phases) header += "," + p + "_s";
  return header + ",bytes_h2d,bytes_d2h";
}

// Phase seconds and bytes of `sim` since the last call (the baseline: construction).
class Deltas {
 public:
  explicit Deltas(Simulation& sim) : sim_(sim), phases_(sim.phase_seconds()), bytes_(sim.backend().traffic_total()) {}
  std::pair<std::vector<double>, std::array<long, 2>> next() {
    std::vector<double> d = sim_.phase_seconds();
    for (size_t p = 0; p < d.size(); ++p) d[p] -= phases_[p];
    phases_ = sim_.phase_seconds();
    const Traffic now = sim_.backend().traffic_total();
    const std::array<long, 2> b = {now.h2d - bytes_.h2d, now.d2h - bytes_.d2h};
    bytes_ = now;
    return {d, b};
  }

 private:
  Simulation& sim_;
  std::vector<double> phases_;
  Traffic bytes_;
};

class OneDevice final : public Run {
 public:
  OneDevice(const Scene& scene, Simulation& sim) : scene_(scene), sim_(sim), deltas_(sim) {}
  bool root() const override { return true; }
  long step() override { return sim_.host_state().step; }
  void advance(long stop) override { sim_.advance(stop); }
  std::pair<long, long> totals() override { return sim_.counts(); }
  std::pair<std::vector<double>, std::array<long, 2>> since_last() override { return deltas_.next(); }
  void mark() override { deltas_.next(); }
  bool any(bool mine) override { return mine; }
  const State& whole() override { return sim_.sync(); }
  void agreed(const std::function<void()>& f) override { f(); }
  void save(RunOutputs& out, const State& all, long) override { out.save(all); }
  bool failed(const std::exception& e, State& frozen) override {
    if (!dynamic_cast<const SimulationError*>(&e)) return false;
    frozen = failing_state(sim_.host_state(), sim_.backend().failure().step, scene_.dt);
    return true;
  }
  // With SEMLB_OPENCL_PROFILE set: kernels.csv, the device seconds and launches of each kernel over the run.
  void finish(RunOutputs& out, const State&) override {
    const auto& secs = sim_.backend().kernel_seconds();
    if (secs.empty()) return;
    std::string csv = "kernel,launches,device_s\n";
    for (const auto& [k, t] : secs) {
      const auto n = sim_.backend().launches().find(k);
      csv +=
          k + "," + std::to_string(n == sim_.backend().launches().end() ? 0 : n->second) + "," + format_real(t) + "\n";
    }
    write_file_atomically(out.dir() + "/kernels.csv", csv);
  }
  std::string device() override { return sim_.backend().device_name(); }
  void breakdown(RunSummary& sum) override {
    for (size_t p = 0; p < sim_.phases().size(); ++p)
      sum.phases.push_back(spread_of(sim_.phases()[p], {sim_.phase_seconds()[p]}));
    sum.list = sim_.backend().list_stats();
  }

 private:
  const Scene& scene_;
  Simulation& sim_;
  Deltas deltas_;
};

class Decomposed final : public Run {
 public:
  Decomposed(const Scene& scene, const RunConfig& config, DistributedSimulation& sim, Mpi& mpi, long first)
      : scene_(scene), config_(config), sim_(sim), mpi_(mpi), first_(first), deltas_(sim.local()) {}
  bool root() const override { return mpi_.rank() == 0; }
  long step() override { return sim_.step(); }
  void advance(long stop) override { sim_.advance(stop); }
  std::pair<long, long> totals() override { return sim_.totals(); }
  std::pair<std::vector<double>, std::array<long, 2>> since_last() override {
    auto [mine, bytes] = deltas_.next();
    std::vector<double> slowest(mine.size(), 0.0);
    const auto all = mpi_.allgather(mine);
    for (size_t i = 0; i < all.size(); ++i) slowest[i % mine.size()] = std::max(slowest[i % mine.size()], all[i]);
    std::vector<double> summed = {static_cast<double>(bytes[0]), static_cast<double>(bytes[1])};
    mpi_.allreduce_sum(summed);
    return {slowest, {static_cast<long>(summed[0]), static_cast<long>(summed[1])}};
  }
  void mark() override { deltas_.next(); }
  bool any(bool mine) override { return mpi_.allreduce_max(mine ? 1 : 0) > 0; }
  const State& whole() override { return gathered_ = sim_.gather(); }
  void agreed(const std::function<void()>& f) override { agree(mpi_, f); }
  void save(RunOutputs& out, const State& all, long stop) override {
    const auto balancer = sim_.checkpoint();
    out.save(all, &balancer);
    if (scene_.record_workload && scene_.checkpoint_every > 0 &&
        stop % scene_.checkpoint_every == 0)  // a restart continues it
      sim_.write_workload(config_.out_dir + "/workload.h5", config_.command_line, config_.git_revision);
  }
  bool failed(const std::exception& e, State& frozen) override {
    const auto* agreed = dynamic_cast<const AgreedError*>(&e);
    if (!agreed || agreed->failed_step < 0) return false;
    frozen = failing_state(sim_.gather(), agreed->failed_step, scene_.dt);  // every rank is here
    return true;
  }
  void finish(RunOutputs&, const State&) override {
    if (scene_.record_workload)
      sim_.write_workload(config_.out_dir + "/workload.h5", config_.command_line, config_.git_revision);
    namespace rt = rank_times;
    std::string rows;
    for (const char* c : rt::kColumns) (rows += rows.empty() ? "" : ",") += c;
    rows += "\n";
    for (const auto& row : earlier_rows(config_.out_dir + "/" + rt::kFile, first_)) rows += row + "\n";  // a restart's
    for (const auto& iv : sim_.intervals())
      for (size_t r = 0; r < iv.times.size(); ++r) {
        const std::map<std::string_view, std::string> field = {
            {rt::kStep, std::to_string(iv.step)},
            {rt::kRank, std::to_string(r)},
            {rt::kComputeS, format_real(iv.times[r])},
            {rt::kExchangeS, format_real(iv.exchange[r])},
            {rt::kMigrateS, format_real(iv.migrate[r])},
            {rt::kImbalance, format_real(iv.imbalance)},
            {rt::kMovedSlices, std::to_string(iv.moved)},
            {rt::kWallS, format_real(iv.wall[r])},
            {rt::kDeviceS, format_real(iv.device[r])},
            {rt::kExchangeBytes, std::to_string(static_cast<long>(iv.exchange_bytes[r]))},
            {rt::kMigrateBytes, std::to_string(static_cast<long>(iv.migrate_bytes[r]))},
            {rt::kDevicePairS, format_real(iv.device_pair[r])},
            {rt::kDeviceListS, format_real(iv.device_list[r])},
            {rt::kDeviceCellsS, format_real(iv.device_cells[r])}};
        for (size_t c = 0; c < rt::kColumns.size(); ++c) (rows += c ? "," : "") += field.at(rt::kColumns[c]);
        rows += "\n";
      }
    write_file_atomically(config_.out_dir + "/" + rt::kFile, rows);
  }
  std::string device() override { return sim_.local().backend().device_name(); }
  void breakdown(RunSummary& sum) override {
    const auto& names = sim_.local().phases();
    const auto all = mpi_.allgather(sim_.local().phase_seconds());  // rank-major: rank r's phases at r * names.size()
    const size_t ranks = names.empty() ? 0 : all.size() / names.size();
    for (size_t p = 0; p < names.size(); ++p) {
      std::vector<double> per_rank;
      for (size_t r = 0; r < ranks; ++r) per_rank.push_back(all[r * names.size() + p]);
      sum.phases.push_back(spread_of(names[p], per_rank));
    }
    std::vector<double> exchange(mpi_.size(), 0.0), migration(mpi_.size(), 0.0);
    for (const auto& iv : sim_.intervals())
      for (size_t r = 0; r < iv.exchange.size() && r < exchange.size(); ++r) {
        exchange[r] += iv.exchange[r];
        migration[r] += iv.migrate[r];
      }
    if (!sim_.intervals().empty()) {  // timed per rebalancing interval: without one they would read 0
      sum.phases.push_back(spread_of("exchange", exchange));
      sum.phases.push_back(spread_of("migration", migration));
      sum.phases_note = "exchange and migration: over the " + std::to_string(sim_.intervals().size()) +
                        " rebalancing intervals, to step " + std::to_string(sim_.intervals().back().step) +
                        "; after the last one they count in other";
    } else {
      sum.phases_note =
          "exchange and migration: no rebalancing interval ended (decomposition.rebalance_every); they "
          "count in other";
    }
    sum.list = sim_.local().backend().list_stats();
    std::vector<double> builds = {static_cast<double>(sum.list.builds)};
    mpi_.allreduce_sum(builds);
    sum.ranks = mpi_.size();
    sum.list.builds = static_cast<long>(builds[0]);
  }

 private:
  const Scene& scene_;
  const RunConfig& config_;
  DistributedSimulation& sim_;
  Mpi& mpi_;
  long first_;
  Deltas deltas_;
  State gathered_;  // the last whole()
};

}  // namespace

namespace {
// The known parts of a run's start: loading the program (when main marked it), the tissue, the device's setup.
std::vector<std::pair<std::string, double>> start_parts(double tissue, double device) {
  std::vector<std::pair<std::string, double>> parts;
  if (main_started_seconds() > 0) parts.emplace_back("load", main_started_seconds());
  parts.emplace_back("tissue", tissue);
  parts.emplace_back("device", device);
  return parts;
}
}  // namespace

void check_scene(const Scene& scene) {
  check_tissue(scene);
  (void)backend_settings(scene.backend);
  (void)make_effects(scene);
  (void)Decomposition::from_scene(scene, 1);
}

RunSummary run_scene(Scene& scene, const RunConfig& config) {
  const auto t0 = std::chrono::steady_clock::now();
  State initial = config.restart.empty() ? make_tissue(scene) : read_state(config.restart);
  if (!config.restart.empty() && scene.auto_box) fit_box(scene, initial);  // the tissue section is not used
  check_steps_ahead(scene, config, initial);
  Decomposition::from_scene(scene, 1);  // a scene meant for mpirun is checked on one device too
  const long first = initial.step;
  const double tissue = seconds_since(t0);
  Simulation sim(scene, std::move(initial));  // all input checked before anything is written
  const double device = seconds_since(t0) - tissue;
  RunOutputs out(scene, config, first, run_header(sim.phases()),
                 {{"git_revision", config.git_revision}, {"scene", scene.name}, {"backend", sim.backend().name()}});
  OneDevice run(scene, sim);
  RunSummary sum = drive(run, scene, config, first, &out);
  sum.start_parts = start_parts(tissue, device);
  return sum;
}

// Every error is collective (docs/engine.md "Failures"): the setup, rank 0's files and the run's own checks
// are agreed on by all ranks (AgreedError); anything else is one rank's alone and aborts the job.
RunSummary run_scene_decomposed(Scene& scene, const RunConfig& config, Mpi& mpi) {
  scene.backend.local_rank = mpi.local_rank();
  const bool root = mpi.rank() == 0;
  State initial;
  std::unique_ptr<DistributedSimulation> sim;
  const auto t0 = std::chrono::steady_clock::now();
  double tissue = 0;
  agree(mpi, [&] {  // all input checked here, before anything is written
    initial = config.restart.empty() ? make_tissue(scene) : read_state(config.restart);
    if (!config.restart.empty() && scene.auto_box) fit_box(scene, initial);
    check_steps_ahead(scene, config, initial);
    const auto restored = config.restart.empty() ? std::nullopt : read_decomposition(config.restart);
    if (restored && scene.auto_box)
      std::tie(scene.box_lo[0], scene.box_hi[0]) = std::pair(restored->x_lo, restored->x_hi);
    tissue = seconds_since(t0);
    sim = std::make_unique<DistributedSimulation>(scene, initial, mpi, root ? config.out_dir + "/trace.jsonl" : "",
                                                  restored);
  });
  const double device = seconds_since(t0) - tissue;  // rank 0's: its slab's setup and the collectives with it
  const long first = initial.step;
  std::unique_ptr<RunOutputs> out;  // rank 0 writes every file; the per-phase columns are each the slowest rank's
  agree(mpi, [&] {
    if (root)
      out = std::make_unique<RunOutputs>(scene, config, first, run_header(sim->local().phases()),
                                         std::map<std::string, std::string>{{"git_revision", config.git_revision},
                                                                            {"scene", scene.name},
                                                                            {"backend", sim->local().backend().name()},
                                                                            {"ranks", std::to_string(mpi.size())}});
  });
  if (root && !sim->restarted().empty()) std::cerr << "semlb sim: restart: " << sim->restarted() << "\n";
  Decomposed run(scene, config, *sim, mpi, first);
  RunSummary sum = drive(run, scene, config, first, out.get());
  sum.start_parts = start_parts(tissue, device);
  return sum;
}

}  // namespace semlb::engine
