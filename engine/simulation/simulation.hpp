// One simulation on one backend: the per-step element stage, the periodic cell stage, phase timers
// and failure detection (a failing kernel stops the run with the step, element and quantity).
#pragma once
#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "backends/backend.hpp"
#include "device_turns.hpp"
#include "effects/effect.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A numerical failure during the run (exit code 1): "step S: element E (cell C, slot K): QUANTITY ...".
struct SimulationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The points of a step where the decomposed run (decomposition/distributed.cpp) acts, as LAMMPS gives a fix typed
// hook points (Fix::setmask, "Modify the input script"): a StepHooks says which points it takes in mask(), and the
// simulation calls those only. Every step: before_forces before the force effects' local parts (selects the bands),
// post_exchange once the first local part is enqueued (posts them; timed apart from the phase),
// before_nonlocal_forces before the non-local parts (waits for the bands and sets the ghosts); progress while the
// device computes a phase (when `profile` waits for it: MPI progress of the bands); at each cell update
// before_cells and after_cells around the stage (a recording run's W_s before it; the cell migration after it);
// failure_check in place of Simulation::check (a collective check across ranks).
class StepHooks {
 public:
  enum Point : unsigned {
    kBeforeForces = 1u << 0,
    kPostExchange = 1u << 1,
    kBeforeNonlocalForces = 1u << 2,
    kProgress = 1u << 3,
    kBeforeCells = 1u << 4,
    kAfterCells = 1u << 5,
    kFailureCheck = 1u << 6,
  };
  virtual ~StepHooks() = default;
  virtual unsigned mask() const = 0;  // the Points taken, or-ed
  virtual void before_forces() {}
  virtual void post_exchange() {}
  virtual void before_nonlocal_forces() {}
  virtual void progress() {}
  virtual void before_cells() {}
  virtual void after_cells() {}
  virtual void failure_check() {}
};

class Simulation {
 public:
  // Builds the backend and the scene's effects (InputError on bad parameters) and uploads `state`. `device_timers`:
  // the backend times the step's kernels on the device (Backend::step_device_seconds; decomposition.timing: device).
  Simulation(const Scene& scene, State state, bool device_timers = false);
  // Runs until state().step == target; `profile` synchronises after every phase for honest timers.
  void advance(long target);
  // The host state with current positions (downloads them from the backend).
  const State& sync();
  // Owned cells and elements now, without a download (Backend::counts).
  std::pair<long, long> counts() const { return backend_->counts(state_); }
  // The host state as of the last sync (after a cell stage on the device its cells are stale until then).
  const State& host_state() const { return state_; }
  Backend& backend() { return *backend_; }
  const Grid& grid() const { return grid_; }
  const std::vector<std::string>& phases() const { return phases_; }
  const std::vector<double>& phase_seconds() const { return seconds_; }  // accumulated, per phase
  bool has_cell_effects() const { return has_cell_effects_; }
  // The growth phase of the first effect that has a growth cycle (Effect::growth_phase), at the current
  // time; 0 when none has.
  double growth_phase() const;
  // The cell stage once, now, on the backend (Backend::update_cells with the cell effects' rules), then the grid
  // refit. advance() runs it every time.cell_update_every steps; `semlb bench cells` calls it directly.
  void update_cells();
  // Accumulated seconds of the cell stage's parts: "stage" (the backend's cell stage; for the C++ backends
  // with their download and upload) and "grid" (bounding box and grid refit); honest only under `profile`.
  const std::vector<std::pair<std::string, double>>& cell_stage_seconds() const { return cell_parts_; }
  bool profile = true;
  // Throws SimulationError if a kernel recorded a failure.
  void check();

  // The decomposed run's hooks (StepHooks; null: none, the default). The simulation does not own them; they must
  // outlive every advance() and update_cells() made while they are set.
  void set_hooks(StepHooks* hooks) { hooks_ = hooks; }
  // Ranks sharing one device (decomposition.device_sharing: turns): when set, every piece of device work of this
  // simulation (each force part, integration, the cell stage, the failure read, a download) runs in a turn, and so
  // should the decomposed run's own device work (in_turn); null: no turns.
  DeviceTurns* turns = nullptr;
  // f() and a finish() of the backend's queue within one turn on the device (just f() and nothing else without turns).
  template <class F>
  void in_turn(F&& f) {
    if (!turns) return f();
    turns->acquire();
    try {
      f();
      backend_->finish();
    } catch (...) {
      turns->release();
      throw;
    }
    turns->release();
  }
  State& state() { return state_; }  // the host state, for the decomposed run to edit, then reload()
  void reload();                     // uploads state() again and refits the grid
  void refit_grid();                 // after the backend's elements changed (a migration)

 private:
  void step_once();
  template <class F>
  void timed(size_t phase, F&& f);
  bool hooked(StepHooks::Point p) const { return hooks_ && (hooks_->mask() & p); }
  void wait_for_device();  // the backend's finish(), with the progress hook while it waits when taken
  void checked();          // the failure_check hook when taken, else check()

  Scene const* scene_;
  State state_;
  std::unique_ptr<Backend> backend_;
  std::vector<std::unique_ptr<Effect>> effects_;
  Grid grid_;
  std::vector<std::string> phases_;
  std::vector<double> seconds_;
  std::vector<std::pair<std::string, double>> cell_parts_;
  bool has_cell_effects_ = false;
  CellRules rules_{};
  StepHooks* hooks_ = nullptr;
};

}  // namespace semlb::engine
