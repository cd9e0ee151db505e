// Simulation loop: forces -> integrate -> post-integration moves every step; cell effects every
// cell_update_every steps on the backend (the device for OpenCL), with a failure check before each.
#include "simulation.hpp"

#include <chrono>
#include <sstream>

#include "effects/cell_fields.hpp"
#include "pairs/pair_term.hpp"
#include "model/tissue.hpp"

namespace semlb::engine {
namespace {
// The scene's backend settings with the pair term it lists (the OpenCL program is built for it) and the device timers.
BackendConfig backend_config(const Scene& scene, bool device_timers) {
  BackendConfig c = scene.backend;
  if (const std::string term = scene_pair_term(scene); !term.empty()) c.pair_term = term;
  c.device_timing = device_timers;
  return c;
}
}  // namespace

Simulation::Simulation(const Scene& scene, State state, bool device_timers)
    : scene_(&scene),
      state_(std::move(state)),
      backend_(make_backend(backend_config(scene, device_timers))),
      effects_(make_effects(scene)) {
  grid_ = Grid::cover(scene.box_lo, scene.box_hi, scene.cutoff);
  std::vector<std::string> listed;
  for (const auto& e : effects_) {
    e->prepare(state_);
    listed.push_back(e->name());
    if (e->adds_forces()) phases_.push_back(e->name());
  }
  declare_cell_fields(state_, listed);  // the per-cell fields the listed effects declare (cell_fields.hpp)
  phases_.push_back("integrate");
  for (const auto& e : effects_)
    if (e->moves_after_integration()) phases_.push_back(e->name());
  for (const auto& e : effects_) has_cell_effects_ = has_cell_effects_ || e->changes_cells();
  rules_ = cell_rules_of(effects_, state_, scene.backend.precision == "float");  // in the registered order
  if (has_cell_effects_) {
    phases_.push_back("cells");
    backend_->require_cells();
  }
  cell_parts_ = {{"stage", 0.0}, {"grid", 0.0}};
  seconds_.assign(phases_.size(), 0.0);
  PhaseScope phase(*backend_, "upload");
  backend_->upload(state_);
}

template <class F>
void Simulation::timed(size_t phase, F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  in_turn([&] {
    f();
    if (profile) wait_for_device();
  });
  seconds_[phase] += seconds_since(t0);
}

void Simulation::wait_for_device() {
  if (hooked(StepHooks::kProgress))
    backend_->finish_while([this] { hooks_->progress(); });
  else
    backend_->finish();
}

void Simulation::checked() { hooked(StepHooks::kFailureCheck) ? hooks_->failure_check() : check(); }

void Simulation::advance(long target) {
  while (state_.step < target) step_once();
  PhaseScope checking(*backend_, "check");
  checked();
}

void Simulation::reload() {
  PhaseScope phase(*backend_, "upload");
  backend_->upload(state_);
  refit_grid();
}

// `domain: auto` follows the tissue as it spreads and stratifies; the grid only speeds up the neighbour
// search (sums are order-independent), so refitting it never changes the result.
void Simulation::refit_grid() {
  if (scene_->auto_box) {  // the box of the backend's elements: the host state may be stale
    const auto b = backend_->bounds();
    const auto [lo, hi] = padded_box(b[0], b[1], scene_->cutoff);
    grid_ = Grid::cover(lo, hi, scene_->cutoff);
  }
}

// A decomposed step (StepHooks, distributed.cpp; docs/engine.md, "Overlap of the ghost exchange with force work"):
// before_forces selects and downloads the bands; the first force effect's local part is enqueued, post_exchange
// posts the bands (its time is the exchange's, not the phase's), and under `profile` MPI progresses (`progress`)
// while the device computes; before_nonlocal_forces waits for the bands and sets the ghosts; the non-local parts.
void Simulation::step_once() {
  const long step = state_.step;
  size_t phase = 0;
  if (hooked(StepHooks::kBeforeForces)) hooks_->before_forces();
  PhaseScope in_step(*backend_, "step");
  backend_->zero_forces();
  const size_t first_force = phase;
  bool posted = !hooked(StepHooks::kPostExchange);
  const auto post = [&] {  // seconds spent posting
    const auto t0 = std::chrono::steady_clock::now();
    hooks_->post_exchange();
    posted = true;
    return seconds_since(t0);
  };
  for (const auto& e : effects_)
    if (e->adds_forces()) {
      const auto t0 = std::chrono::steady_clock::now();
      double posting = 0;
      in_turn([&] {  // without turns: a decomposed run's bands are posted here, while the device computes
        e->forces(*backend_, grid_);
        posting = posted ? 0.0 : post();
        if (profile) wait_for_device();
      });
      seconds_[phase++] += seconds_since(t0) - posting;
    }
  if (!posted) post();
  if (hooked(StepHooks::kBeforeNonlocalForces)) hooks_->before_nonlocal_forces();
  size_t force = first_force;
  for (const auto& e : effects_)
    if (e->adds_forces()) timed(force++, [&] { e->nonlocal_forces(*backend_, grid_); });
  timed(phase++, [&] { backend_->integrate(scene_->dt / scene_->friction, scene_->max_displacement, step); });
  for (const auto& e : effects_)
    if (e->moves_after_integration()) timed(phase++, [&] { e->after_integration(*backend_, step); });
  state_.step = step + 1;
  state_.time = static_cast<double>(state_.step) * scene_->dt;
  if (has_cell_effects_ && state_.step % scene_->cell_update_every == 0) {
    // The failure check and the cell migration are collective in a decomposed run: outside the timers, so
    // that a rank's computation time holds its own work and not its wait for the slowest rank.
    {
      PhaseScope checking(*backend_, "check");
      checked();
    }
    if (hooked(StepHooks::kBeforeCells)) hooks_->before_cells();
    timed(phase, [&] { update_cells(); });
    if (hooked(StepHooks::kAfterCells)) hooks_->after_cells();
  }
}

void Simulation::update_cells() {
  PhaseScope phase(*backend_, "cells");
  auto t0 = std::chrono::steady_clock::now();
  const auto lap = [&](size_t part) {  // closes a part; under profile after the queued work finished
    if (profile) backend_->finish();
    cell_parts_[part].second += seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
  };
  const double elapsed = scene_->cell_stage_h();
  cellrules::semlb_cell_stage_at(&rules_, state_.time);
  bool changed = false;
  in_turn([&] {
    changed = backend_->update_cells(state_, rules_, scene_->seed, elapsed, state_.step);
    for (const auto& e : effects_)
      if (e->changes_cells()) changed = e->after_cell_stage(*backend_, state_) || changed;
  });
  lap(0);
  if (changed) refit_grid();
  lap(1);
}

const State& Simulation::sync() {
  PhaseScope phase(*backend_, "output");
  in_turn([&] { backend_->download(state_); });
  return state_;
}

void Simulation::check() {
  Failure f;
  in_turn([&] { f = backend_->failure(); });
  if (!f.failed()) return;
  in_turn([&] { backend_->download(state_); });
  long cell = 0;
  while (cell + 1 < state_.cells() && state_.cell_first[cell + 1] <= f.element) ++cell;
  std::ostringstream m;
  m << "step " << f.step << ": element " << f.element << " (cell " << state_.cell_id[cell] << ", slot "
    << f.element - state_.cell_first[cell] << "): " << f.quantity() << " (position " << state_.position[3 * f.element]
    << ", " << state_.position[3 * f.element + 1] << ", " << state_.position[3 * f.element + 2] << "; ";
  if (f.code == 3)
    m << "the |forces| on it add up to more than 2^30 force units, beyond which its fixed-point sums, int64 in units of"
      << " 2^-32, could wrap): fewer partners within the cutoff or weaker pair forces (U0, V0)";
  else
    m << "limit " << scene_->max_displacement << " um per step at time.dt = " << scene_->dt << " h): lower time.dt";
  throw SimulationError(m.str());
}

double Simulation::growth_phase() const {
  for (const auto& e : effects_)
    if (const auto phase = e->growth_phase(state_.time)) return *phase;
  return 0.0;
}

}  // namespace semlb::engine
