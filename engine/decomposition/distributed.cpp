// Decomposed run: ghosts every step, cell migration after cell updates and rebalancing, decisions by
// the controllers' policies on rank 0 (broadcast), traces in `semlb replay`'s format.
#include "distributed.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <unistd.h>

#include "controllers/chains.hpp"
#include "common/errors.hpp"
#include "controllers/metrics.hpp"
#include "controllers/partition.hpp"
#include "common/text_io.hpp"
#include "controllers/trace.hpp"
#include "physics/cpu_physics.hpp"
#include "effects/effect.hpp"
#include "model/tissue.hpp"
#include "simulation/device_turns.hpp"
#include "wire.hpp"

namespace semlb::engine {
namespace {

// Bands reach a little beyond the cutoff: devices compare in their own precision, and a surplus ghost
// changes nothing (it lies beyond the cutoff of every owned element).
constexpr double kGhostSlack = 0.01;

// Regions of the tissue over which a recording run times the local pair forces (WorkloadEvent::slice_seconds):
// contiguous slices of about equal elements, at most this many (fewer when the slices are fewer).
constexpr int kCostRegions = 32;

// A name for this job's turn files on this node without a collective (the constructor's errors are agreed on after
// it, so it may not wait for other ranks): the ranks of one job on one node are children of one launcher process
// (mpirun's daemon, srun's step daemon), whose pid no other running job shares.
std::string job_name() { return "p" + std::to_string(getppid()); }

}  // namespace

DistributedSimulation::DistributedSimulation(const Scene& scene, const State& tissue, Mpi& mpi,
                                             const std::string& trace_path,
                                             const std::optional<DecompositionCheckpoint>& restored)
    : scene_(&scene), mpi_(&mpi), dec_(Decomposition::from_scene(scene, mpi.size())) {
  const auto initial = dec_.initial == "workload"
                           ? optimal_partition(slice_workload(tissue, dec_, scene.cutoff), mpi.size(), dec_.min_width)
                           : uniform_partition(mpi.size(), dec_.slices);
  balancer_ = std::make_unique<Balancer>(dec_.policy, make_policy(dec_.policy, dec_.params), dec_.slices,
                                         dec_.min_width, initial);
  cells_at_event_ = static_cast<long>(tissue.cells());
  if (restored && (restored->ranks != mpi.size() || restored->policy != dec_.policy ||
                   restored->slices != dec_.slices || restored->min_width != dec_.min_width)) {
    restarted_ = "the checkpoint's balancer is for " + std::to_string(restored->ranks) + " ranks with policy '" +
                 restored->policy + "' on " + std::to_string(restored->slices) + " slices (min width " +
                 std::to_string(restored->min_width) + "); this run has " + std::to_string(mpi.size()) + " with '" +
                 dec_.policy + "' on " + std::to_string(dec_.slices) + " (min width " + std::to_string(dec_.min_width) +
                 "): rebalancing restarts from the " + dec_.initial + " partition at event 0";
  } else if (restored) {
    try {
      balancer_->load_state(restored->balancer);
    } catch (const InputError& e) {
      throw InputError(restored->file + ": group /decomposition: " + e.what());
    }
    cells_at_event_ = restored->cells_at_event;
  }
  State mine;  // every rank holds the whole tissue here: each keeps its own cells, nothing is sent
  split_by_owner(tissue, dec_, balancer_->boundaries(), mpi.rank(), mine);
  sim_ = std::make_unique<Simulation>(scene, std::move(mine), dec_.timing == "device");
  sim_->set_hooks(&hooks_);
  // Every rank opens the file here, before the collectives that follow the construction: none can have removed it
  // (at its end) before the last one opens it.
  if (dec_.device_sharing == "turns") {
    turns_ = std::make_unique<DeviceTurns>(DeviceTurns::path_for(job_name(), sim_->backend().device_key()));
    sim_->turns = turns_.get();
  }
  trace_path_ = mpi.rank() == 0 ? trace_path : "";  // opened at the first event: nothing is written before
  if (!trace_path_.empty() && balancer_->event() > 0 && std::filesystem::exists(trace_path_))
    for (const auto& line : split(read_file(trace_path_), '\n'))  // a restart keeps the events before its own
      if (!line.empty() && parse_trace_line(line, trace_path_, 0).obs.event < balancer_->event())
        trace_kept_ += line + "\n";
  if (scene.record_workload && mpi.rank() == 0 && !trace_path.empty() &&
      balancer_->event() > 0) {  // a restart keeps the events before its own
    const auto path = std::filesystem::path(trace_path).parent_path() / "workload.h5";
    if (std::filesystem::exists(path))
      for (auto& e : read_workload(path.string()).events)
        if (e.step <= tissue.step) workload_.push_back(std::move(e));
  }
  // A recording on one rank marks the slices that trigger its neighbour list's builds (WorkloadEvent::list_triggers):
  // on P ranks each list is a rank's own, so the one-rank builds the field describes do not exist; a restart of a
  // recording whose earlier events have none (an older file) continues without them, so that the file stays whole.
  if (tracks_stages() && mpi.size() == 1 && (workload_.empty() || !workload_.front().list_triggers.empty()))
    sim_->backend().track_list_triggers(dec_.x0, dec_.width, dec_.slices);
  if (const char* f = std::getenv("SEMLB_FAULT_INJECT")) {  // "RANK:STEP": a test of one rank's error (docs/engine.md)
    const auto parts = split(f, ':');
    if (parts.size() != 2) throw InputError("SEMLB_FAULT_INJECT: expected RANK:STEP, got '" + std::string(f) + "'");
    fault_rank_ = static_cast<int>(parse_integer(parts[0], "SEMLB_FAULT_INJECT: rank: ", 0, mpi.size() - 1));
    fault_step_ = parse_integer(parts[1], "SEMLB_FAULT_INJECT: step: ", 0);
  }
}

double DistributedSimulation::compute_seconds() const {
  double s = 0;
  for (double p : sim_->phase_seconds()) s += p;
  return s;
}

unsigned DistributedSimulation::Hooks::mask() const {
  unsigned m = kBeforeForces | kAfterCells | kFailureCheck;
  if (d_.dec_.overlap) m |= kPostExchange | kBeforeNonlocalForces | kProgress;
  if (d_.tracks_stages()) m |= kBeforeCells;
  return m;
}

// Owned elements within the cutoff of a neighbour's elements go to that neighbour; only neighbours
// exchange, so no two ranks further apart may hold elements within the cutoff of each other (checked here,
// over all pairs of ranks). The check and the per-step failure flag (set by the previous step's
// integration, seen before the next step moves anything) are agreed from one allgather, so every rank stops at
// the same step. The backend selects both bands on its device in one pass (Backend::bands: only the x range, the
// flag, two counts and the band elements cross to the host) and keeps their union as the non-local forces'
// items. With decomposition.overlap (default) the bands are posted once the local forces are enqueued
// (post_exchange) and waited for before the non-local forces (finish_exchange); without it all three run here,
// before any force (docs/engine.md, "Overlap of the ghost exchange with force work").
void DistributedSimulation::start_exchange() {
  const int r = mpi_->rank(), P = mpi_->size();
  if (P == 1) return;  // no neighbours; the failure is caught at the next check, the state frozen meanwhile
  const auto t0 = std::chrono::steady_clock::now();
  Backend& b = sim_->backend();
  PhaseScope phase(b, "exchange");
  std::array<double, 2> extent{};
  Failure failure;
  sim_->in_turn([&] {
    extent = b.x_extent();
    failure = b.failure();
  });
  const auto [lo, hi] = extent;
  const auto gathered = mpi_->allgather({lo, hi, static_cast<double>(failure.step)});  // 3 per rank
  auto los = [&](int q) { return gathered[3 * q]; };
  auto his = [&](int q) { return gathered[3 * q + 1]; };
  bool failed = false;
  for (int q = 0; q < P; ++q) failed = failed || gathered[3 * q + 2] >= 0;
  if (failed) collective_check();  // every rank sees the same flags: all call it, all throw
  const double cut = scene_->cutoff, reach = cut * (1 + kGhostSlack);
  for (int p = 0; p < P; ++p)  // the same verdict on every rank: all throw it together
    for (int q = p + 2; q < P; ++q)
      if (los(q) - reach < his(p)) {
        std::ostringstream m;
        m << "step " << step() << ": ranks " << p << " and " << q
          << " hold elements within the cutoff of each other (x up to " << his(p) << " and from " << los(q)
          << " um) but only neighbouring ranks exchange ghosts: a cell reaches"
          << " further than one cutoff from its slab (raise decomposition.min_width)";
        throw AgreedError(m.str(), 1);
      }
  // Every ghost then lies at least `reach` (> cutoff) beyond the band limits: the bands' selection is exact
  // as the non-local items (Backend::pair_forces_nonlocal).
  Ghosts left, right;
  sim_->in_turn(
      [&] { b.bands(r > 0 ? his(r - 1) + reach : -INFINITY, r + 1 < P ? los(r + 1) - reach : INFINITY, left, right); });
  send_left_ = pack_band(left);
  send_right_ = pack_band(right);
  exchange_s_ += seconds_since(t0);
  if (!dec_.overlap) {
    post_exchange();
    finish_exchange();
  }
}

// Posts the bands selected by start_exchange(): the sizes are swapped at once (8 bytes, blocking), the bands by
// MPI_Isend/MPI_Irecv, owned by pending_ (freed if anything throws before the wait).
void DistributedSimulation::post_exchange() {
  if (mpi_->size() == 1) return;
  const auto t0 = std::chrono::steady_clock::now();
  const int r = mpi_->rank(), P = mpi_->size();
  const int below = r > 0 ? r - 1 : MPI_PROC_NULL, above = r + 1 < P ? r + 1 : MPI_PROC_NULL;
  mpi_->start_sendrecv(send_left_, below, above, from_above_, 1, pending_);   // tags 1, 2: bands sent down
  mpi_->start_sendrecv(send_right_, above, below, from_below_, 3, pending_);  // tags 3, 4: bands sent up
  exchange_bytes_ += static_cast<double>((r > 0 ? send_left_.size() : 0) + (r + 1 < P ? send_right_.size() : 0));
  if (r == fault_rank_ && step() == fault_step_)  // with its bands in flight: Requests frees them, MPI_Abort follows
    throw std::runtime_error("step " + std::to_string(step()) + ": fault injected by SEMLB_FAULT_INJECT");
  exchange_s_ += seconds_since(t0);
}

// Waits for the bands posted by post_exchange() and sets them as the backend's ghosts (their upload is enqueued
// without a host sync; the device runs it before the non-local forces). exchange_s counts the time a rank
// spends here and in the two calls before: the wait beyond its local forces, not the time the bands travelled
// while the device computed.
void DistributedSimulation::finish_exchange() {
  if (mpi_->size() == 1) return;
  const auto t0 = std::chrono::steady_clock::now();
  Backend& b = sim_->backend();
  PhaseScope phase(b, "exchange");
  pending_.wait();
  Ghosts g;
  for (const auto* bytes : {&from_above_, &from_below_}) unpack_band(*bytes, g);
  int cell = static_cast<int>(sim_->counts().first) - 1;  // ghost cells are numbered after the owned ones
  for (long e = 0; e < g.elements(); ++e) {               // a band holds each cell's elements contiguously
    if (e == 0 || cell_id_of_key(g.keys[e]) != cell_id_of_key(g.keys[e - 1])) ++cell;
    g.info[e] = phys64::semlb_info_pack(cell, phys64::semlb_info_type(g.info[e]));
  }
  sim_->in_turn([&] { b.set_ghosts(g); });  // kept on the backend for the next W_s
  exchange_s_ += seconds_since(t0);
}

// Owners from the centroids and the packing of the leavers run on the backend (the device for OpenCL): only
// the cells that change owner cross to the host, and nothing when none does (Backend::take_leavers).
void DistributedSimulation::migrate_cells() {
  const auto t0 = std::chrono::steady_clock::now();
  Backend& b = sim_->backend();
  if (stage_pending_) stage_work_after();  // a cell stage ran (an event between cell stages has none)
  PhaseScope phase(b, "migration");
  if (step() % dec_.rebalance_every == 0) decide(measure());  // new boundaries first
  State leavers;
  std::vector<int> owner;
  sim_->in_turn([&] { b.take_leavers(sim_->state(), dec_, balancer_->boundaries(), mpi_->rank(), leavers, owner); });
  std::vector<Writer> out(mpi_->size());
  for (long c = 0; c < leavers.cells(); ++c) pack_cell(out[owner[c]], leavers, c);
  std::vector<std::vector<char>> parts;
  for (auto& w : out) parts.push_back(std::move(w.bytes));
  for (int q = 0; q < mpi_->size(); ++q)
    if (q != mpi_->rank()) migrate_bytes_ += static_cast<double>(parts[q].size());
  State arrivals = empty_like(sim_->host_state());
  for (const auto& bytes : mpi_->alltoall(parts)) unpack_cells(bytes, arrivals);
  arrivals.reindex();
  if (leavers.cells() > 0 || arrivals.cells() > 0)  // else the backend holds exactly these cells
    sim_->in_turn([&] {
      b.append_cells(sim_->state(), arrivals);
      sim_->refit_grid();
      b.finish();
    });
  migrate_s_ += seconds_since(t0);
}

Grid DistributedSimulation::work_grid_all_ranks() {
  const auto [cells, elements] = sim_->counts();
  std::array<std::array<double, 3>, 2> b{};
  if (elements > 0) alone_in_turn([&] { b = sim_->backend().bounds(); });
  const auto all = mpi_->allgather({elements > 0 ? 1.0 : 0.0, b[0][0], b[0][1], b[0][2], b[1][0], b[1][1], b[1][2]});
  std::array<double, 3> lo{}, hi{};
  bool any = false;
  for (int q = 0; q < mpi_->size(); ++q) {  // min and max are exact: the box of the whole tissue, as on one device
    const double* v = &all[7 * q];
    if (v[0] == 0) continue;
    for (int d = 0; d < 3; ++d) {
      lo[d] = any ? std::fmin(lo[d], v[1 + d]) : v[1 + d];
      hi[d] = any ? std::fmax(hi[d], v[4 + d]) : v[4 + d];
    }
    any = true;
  }
  return work_grid(lo, hi, scene_->cutoff);
}

bool DistributedSimulation::tracks_stages() const {
  return scene_->record_workload && sim_->backend().has_device_timers();
}

void DistributedSimulation::stage_work_before() {
  PhaseScope phase(sim_->backend(), "workload");  // outside the step's timers
  stage_grid_ = work_grid_all_ranks();  // one grid for both counts: the stage's refit must not change the bins
  stage_work_ = global_slice_work(stage_grid_);
  stage_pending_ = true;
}

void DistributedSimulation::stage_work_after() {
  PhaseScope phase(sim_->backend(), "workload");
  const std::vector<double> after = global_slice_work(stage_grid_);
  if (stage_changes_.empty()) stage_changes_.assign(dec_.slices, 0);
  const int64_t bit = int64_t{1} << std::min(stage_, 62);
  for (int s = 0; s < dec_.slices; ++s)
    if (after[s] != stage_work_[s]) stage_changes_[s] |= bit;
  ++stage_;
  stage_pending_ = false;
}

std::vector<double> DistributedSimulation::global_slice_work() { return global_slice_work(work_grid_all_ranks()); }

std::vector<double> DistributedSimulation::global_slice_work(const Grid& g) {
  CountReduce reduce;
  if (mpi_->size() > 1) reduce = [this](std::vector<int>& counts) { mpi_->allreduce_sum(counts); };
  std::vector<double> work;
  alone_in_turn([&] { work = sim_->backend().slice_work(sim_->state(), dec_, g, reduce); });
  mpi_->allreduce_sum(work);  // integers below 2^53: exact in any order
  return work;
}

Measurement DistributedSimulation::measure() {
  Backend& b = sim_->backend();
  const double now = compute_seconds(), device_now = b.step_device_seconds();
  const std::map<std::string, double> kernels_now = b.step_kernel_seconds();
  std::map<std::string, double> kernels = kernels_now;  // this interval's, by kernel
  for (auto& [k, t] : kernels) t -= kernels_at_event_[k];
  kernels_at_event_ = kernels_now;
  const Backend::DeviceParts parts = Backend::device_parts(kernels);
  constexpr int kPerRank = 9;
  const auto seconds = mpi_->allgather({now - seconds_at_event_, exchange_s_, migrate_s_, device_now - device_at_event_,
                                        exchange_bytes_, migrate_bytes_, parts.pair, parts.list, parts.cells});
  seconds_at_event_ = now;
  device_at_event_ = device_now;
  exchange_s_ = migrate_s_ = exchange_bytes_ = migrate_bytes_ = 0;
  Interval iv{};
  Measurement m;
  for (int r = 0; r < mpi_->size(); ++r) {
    const double* v = &seconds[kPerRank * r];
    iv.wall.push_back(v[0]);
    iv.exchange.push_back(v[1]);
    iv.migrate.push_back(v[2]);
    iv.device.push_back(v[3]);
    iv.exchange_bytes.push_back(v[4]);
    iv.migrate_bytes.push_back(v[5]);
    iv.device_pair.push_back(v[6]);
    iv.device_list.push_back(v[7]);
    iv.device_cells.push_back(v[8]);
    m.times.push_back(dec_.timing == "device" ? v[3] : v[0]);
  }
  auto work = global_slice_work();
  if (scene_->record_workload) {
    WorkloadEvent e;
    e.step = step();
    e.time_h = sim_->host_state().time;
    e.growth_phase = sim_->growth_phase();
    e.slice_work = work;
    for (double t : m.times) e.interval_s += t;  // measured, before decomposition.timing: modelled replaces them
    count_elements(e);
    if (b.has_device_timers()) {
      e.slice_seconds = measured_slice_seconds(e, work, parts.pair, iv.device[mpi_->rank()]);
      e.part_seconds.assign(4, 0.0);
      for (int r = 0; r < mpi_->size(); ++r) {
        const double parts[3] = {iv.device_pair[r], iv.device_list[r], iv.device_cells[r]};
        for (int k = 0; k < 3; ++k) e.part_seconds[k] += parts[k];
      }
      e.part_seconds[3] = std::max(0.0, e.interval_s - e.part_seconds[0] - e.part_seconds[1] - e.part_seconds[2]);
      e.cell_stage_changes = stage_changes_.empty() ? std::vector<int64_t>(dec_.slices, 0) : stage_changes_;
      ListTriggers triggers;
      alone_in_turn([&] { triggers = b.take_list_triggers(); });  // {0, {}} on P ranks or without a list
      e.list_builds = triggers.slices.empty() ? 0 : triggers.builds;
      e.list_triggers = std::move(triggers.slices);
      stage_changes_.assign(dec_.slices, 0);
      stage_ = 0;
    }
    if (mpi_->rank() == 0) workload_.push_back(std::move(e));
  }
  if (dec_.timing == "modelled") m.times = rank_sums(work, balancer_->boundaries());
  double total_work = 0, total_time = 0;
  for (double w : work) total_work += w;
  for (double t : m.times) total_time += t;
  for (double& w : work) w *= total_work > 0 ? total_time / total_work : 0.0;  // W_s scaled to the times
  m.slice_work = std::move(work);
  m.growth_phase = sim_->growth_phase();
  const long cells = totals().first;
  m.growth_event = cells != cells_at_event_;
  cells_at_event_ = cells;
  if (scene_->record_workload && mpi_->rank() == 0) {
    workload_.back().cells = cells;
    workload_.back().growth_event = m.growth_event;
  }
  iv.step = step();
  intervals_.push_back(std::move(iv));
  return m;
}

void DistributedSimulation::count_elements(WorkloadEvent& e) {
  const State& s = sim_->sync();
  const int S = dec_.slices;
  std::vector<double> x(s.elements()), n(S + 2 * (S - 1), 0.0);  // slice elements, then the bands below, then above
  for (long i = 0; i < s.elements(); ++i) {
    x[i] = s.position[3 * i];
    ++n[dec_.slice_of(x[i])];
  }
  std::vector<double> below(S - 1, 0.0), above(S - 1, 0.0);
  add_edge_bands(x, dec_.x0, dec_.width, S, scene_->cutoff * (1 + kGhostSlack), below, above);
  std::copy(below.begin(), below.end(), n.begin() + S);
  std::copy(above.begin(), above.end(), n.begin() + S + (S - 1));
  mpi_->allreduce_sum(n);  // integer counts below 2^53: exact
  e.slice_elements.assign(n.begin(), n.begin() + S);
  e.band_below.assign(n.begin() + S, n.begin() + S + (S - 1));
  e.band_above.assign(n.begin() + S + (S - 1), n.end());
  e.elements = 0;
  for (double v : e.slice_elements) e.elements += static_cast<long>(v);
}

std::vector<double> DistributedSimulation::measured_slice_seconds(const WorkloadEvent& e,
                                                                  const std::vector<double>& work, double pair,
                                                                  double device_s) {
  const int S = dec_.slices, K = std::min(kCostRegions, S);
  // Regions: contiguous slices of about equal elements (the global counts: the same regions on every rank).
  std::vector<int> region(S);
  double total = 0, before = 0;
  for (double n : e.slice_elements) total += n;
  for (int s = 0; s < S; ++s) {
    const double mid = before + e.slice_elements[s] / 2;
    before += e.slice_elements[s];
    region[s] =
        total > 0 ? std::min(K - 1, static_cast<int>(mid * K / total)) : static_cast<int>(static_cast<long>(s) * K / S);
  }
  const State& st = sim_->host_state();  // count_elements synced it
  std::vector<int> group(st.elements());
  for (long i = 0; i < st.elements(); ++i) group[i] = region[dec_.slice_of(st.position[3 * i])];
  Backend& b = sim_->backend();
  std::vector<double> sums;
  {
    PhaseScope phase(b, "workload");  // outside the step's timers
    sim_->in_turn([&] { sums = b.pair_force_seconds(group, K); });
  }
  sums.resize(K, 0.0);
  sums.push_back(pair);
  sums.push_back(std::max(0.0, device_s - pair));
  mpi_->allreduce_sum(sums);
  const double F = sums[K], O = sums[K + 1];
  double timed = 0;
  std::vector<double> region_work(K, 0.0), region_elements(K, 0.0);
  for (int k = 0; k < K; ++k) timed += sums[k];
  for (int s = 0; s < S; ++s) region_work[region[s]] += work[s], region_elements[region[s]] += e.slice_elements[s];
  std::vector<double> out(S, 0.0);
  for (int s = 0; s < S; ++s) {
    const int k = region[s];
    const double n = e.slice_elements[s];
    // the region's measured share of the pair forces, over its slices by W_s (by elements where it has no W_s)
    const double within =
        region_work[k] > 0 ? work[s] / region_work[k] : (region_elements[k] > 0 ? n / region_elements[k] : 0.0);
    const double pair_share = timed > 0 ? sums[k] / timed * within : (total > 0 ? n / total : 0.0);
    out[s] = F * pair_share + (total > 0 ? O * n / total : 0.0);
  }
  return out;
}

void DistributedSimulation::write_workload(const std::string& path, const std::string& command,
                                           const std::string& git_revision) {
  EngineWorkload w;
  w.slices = dec_.slices;
  w.min_width = dec_.min_width;
  w.x0_um = dec_.x0;
  w.slice_width_um = dec_.width;
  w.cutoff_um = scene_->cutoff;
  w.ghost_reach_um = scene_->cutoff * (1 + kGhostSlack);
  w.rebalance_every = dec_.rebalance_every;
  w.ranks = mpi_->size();
  w.scene = scene_->name;
  w.command = command;
  w.git_revision = git_revision;
  w.device = sim_->backend().device_name();
  w.events = workload_;
  if (!w.events.empty() && !w.events.front().slice_seconds.empty())
    w.cost_regions = std::min(kCostRegions, dec_.slices);
  ::semlb::write_workload(path, w);
}

void DistributedSimulation::decide(const Measurement& m) {
  const std::vector<int> before = balancer_->boundaries();
  std::vector<int> next = before;
  agree(*mpi_, [&] {  // rank 0 decides: its errors (a policy's, the trace file's) stop every rank
    if (mpi_->rank() != 0) return;
    const Decision d = balancer_->rebalance(m);
    write_trace(d.trace);
    next = d.boundaries;
  });
  mpi_->broadcast(next, 0);
  if (mpi_->rank() != 0) balancer_->commit(balancer_->observe(m), next);  // every rank's balancer in the same state
  Interval& iv = intervals_.back();
  iv.times = m.times;
  iv.imbalance = global_imbalance(m.times);
  iv.moved = migration(before, next);
}

void DistributedSimulation::write_trace(const TraceEvent& e) {
  if (trace_path_.empty()) return;
  if (!trace_.is_open()) {
    trace_.open(trace_path_, std::ios::trunc);
    if (!trace_) throw std::runtime_error(trace_path_ + ": cannot write");
    trace_ << trace_kept_;
  }
  trace_ << to_json(e).dump() << "\n" << std::flush;
}

DecompositionCheckpoint DistributedSimulation::checkpoint() const {
  return {"",
          mpi_->size(),
          dec_.slices,
          dec_.min_width,
          dec_.policy,
          cells_at_event_,
          dec_.x0,
          dec_.x0 + dec_.width * dec_.slices,
          balancer_->save_state()};
}

void DistributedSimulation::collective_check() {
  std::string message;
  try {
    sim_->check();
  } catch (const SimulationError& e) {
    message = "rank " + std::to_string(mpi_->rank()) + ": " + e.what();
  }
  const Failure f = sim_->backend().failure();
  const auto failed = mpi_->allgather({static_cast<double>(f.step)});  // -1 where none
  int first = -1;  // the rank with the earliest failing step, the lowest such rank
  for (int r = 0; r < mpi_->size(); ++r)
    if (failed[r] >= 0 && (first < 0 || failed[r] < failed[first])) first = r;
  if (first < 0) return;
  mpi_->broadcast(message, first);
  throw AgreedError(message, 1, static_cast<long>(failed[first]));
}

void DistributedSimulation::advance(long target) {
  while (step() < target) {
    const long stop = std::min(target, (step() / dec_.rebalance_every + 1) * dec_.rebalance_every);
    sim_->advance(stop);
    const bool cells_updated = sim_->has_cell_effects() && stop % scene_->cell_update_every == 0;  // migrated there
    if (stop % dec_.rebalance_every == 0 && !cells_updated) migrate_cells();  // syncs, rebalances first
  }
}

std::pair<long, long> DistributedSimulation::totals() {
  const auto [cells, elements] = sim_->counts();
  std::vector<double> n{static_cast<double>(cells), static_cast<double>(elements)};
  mpi_->allreduce_sum(n);
  return {static_cast<long>(n[0]), static_cast<long>(n[1])};
}

State DistributedSimulation::gather() {
  const State& s = sim_->sync();
  Writer w;
  for (long c = 0; c < s.cells(); ++c) pack_cell(w, s, c);
  State all = empty_like(s);
  for (const auto& bytes : mpi_->gather(w.bytes, 0)) unpack_cells(bytes, all);
  all.reindex();
  if (!all.is_canonical()) return all.canonical();
  return all;  // moved out: no copy when the ranks' cells came in id order
}

}  // namespace semlb::engine
