// Timing of the element kernels of a scene (semlb bench engine, the single_device and effects_cost
// experiments), of the host cell stage (semlb bench cells), and the density statistics that make such
// numbers comparable.
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "backends/backend.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

struct TissueStats {
  double per_cutoff_cube = 0;  // element-weighted density: elements per cutoff^3 around an element
  double candidates = 0;       // mean elements in the 27-bin stencil of an element (itself excluded)
  double neighbours = 0;       // mean elements within the cutoff (sampled)
};
TissueStats tissue_stats(const State& state, const Grid& grid, double cutoff, long sample = 20000);

struct Timing {
  long cells = 0, elements = 0, steps = 0;
  double seconds = 0;  // wall time of `steps` steps after the warm-up, device work included
  std::string backend, device;
  std::vector<std::string> phases;
  std::vector<double> phase_seconds;             // with per-phase synchronisation (a second, profiled pass)
  TissueStats stats;                             // of the generated tissue, before the first step
  std::map<std::string, double> kernel_seconds;  // over the timed steps, when the backend profiles
  ListStats list;                                // the neighbour list after the timed steps (skin 0: none)
  long list_builds = 0;                          // list builds during the timed steps
  double element_steps_per_second() const { return seconds > 0 ? static_cast<double>(elements) * steps / seconds : 0; }
};

// The host cell stage (semlb bench cells): seconds per cell update of each part, over `updates` updates
// run back to back on the scene's tissue after one untimed update.
struct CellStageTiming {
  long cells = 0, elements = 0, updates = 0;
  std::string backend, device;
  std::vector<std::pair<std::string, double>> parts;  // "stage", "grid" (Simulation::cell_stage_seconds)
};
CellStageTiming time_cell_stage(Scene& scene, long updates);

// Builds the scene's tissue (and its density statistics), runs `warmup` steps, then times `steps` steps
// without per-phase syncs, then (if profile_steps > 0) that many more with them for the phase breakdown.
Timing time_scene(Scene& scene, long steps, long warmup = 2, long profile_steps = 0);

}  // namespace semlb::engine
