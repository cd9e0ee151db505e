// Scene timing and tissue density statistics.
#include "bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/errors.hpp"
#include "physics/stencil.h"
#include "simulation/simulation.hpp"
#include "io/io.hpp"
#include "model/tissue.hpp"

namespace semlb::engine {

TissueStats tissue_stats(const State& s, const Grid& g, double cutoff, long sample) {
  TissueStats t;
  const long n = s.elements();
  if (n == 0) return t;
  std::vector<long> count(g.bins(), 0), bin(n);
  auto index = [&](int x, int y, int z) { return (static_cast<long>(z) * g.dims[1] + y) * g.dims[0] + x; };
  for (long e = 0; e < n; ++e) {
    const auto b = g.bin_of(&s.position[3 * e]);
    bin[e] = index(b[0], b[1], b[2]);
    ++count[bin[e]];
  }
  const double cube = cutoff * cutoff * cutoff / (g.size[0] * g.size[1] * g.size[2]);
  for (long e = 0; e < n; ++e) {
    const long b = bin[e];
    const int bx = static_cast<int>(b % g.dims[0]), by = static_cast<int>(b / g.dims[0] % g.dims[1]),
              bz = static_cast<int>(b / (static_cast<long>(g.dims[0]) * g.dims[1]));
    t.per_cutoff_cube += static_cast<double>(count[b]) * cube;
    long candidates = 0;
    SEMLB_STENCIL_ROWS(bx, by, bz, g.dims[0], g.dims[1], g.dims[2], first_bin, last_bin)
    for (long k = first_bin; k <= last_bin; ++k) candidates += count[k];
    t.candidates += static_cast<double>(candidates - 1);
  }
  // brute force over a sample (independent of the binning under test): every stride-th element while the pairs
  // stay under 4e9, summed in integers across the threads (the same count on any thread count)
  const long stride = std::max(1L, n / sample);
  const long sampled = std::min((n + stride - 1) / stride, static_cast<long>(std::ceil(4e9 / static_cast<double>(n))));
  long neighbours = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : neighbours)
  for (long i = 0; i < sampled; ++i) {
    const long e = i * stride;
    for (long o = 0; o < n; ++o) {
      double r2 = 0;
      for (int d = 0; d < 3; ++d)
        r2 += (s.position[3 * e + d] - s.position[3 * o + d]) * (s.position[3 * e + d] - s.position[3 * o + d]);
      neighbours += o != e && r2 < cutoff * cutoff;
    }
  }
  t.per_cutoff_cube /= static_cast<double>(n);
  t.candidates /= static_cast<double>(n);
  t.neighbours = static_cast<double>(neighbours) / static_cast<double>(sampled);
  return t;
}

Timing time_scene(Scene& scene, long steps, long warmup, long profile_steps) {
  State tissue = make_tissue(scene);
  Timing t;
  t.stats = tissue_stats(tissue, Grid::cover(scene.box_lo, scene.box_hi, scene.cutoff), scene.cutoff);
  Simulation sim(scene, std::move(tissue));
  t.backend = sim.backend().name();
  t.device = sim.backend().device_name();
  sim.profile = false;
  sim.advance(sim.host_state().step + warmup);
  sim.backend().finish();
  const auto kernels_before = sim.backend().kernel_seconds();
  const long builds_before = sim.backend().list_stats().builds;
  const auto t0 = std::chrono::steady_clock::now();
  sim.advance(sim.host_state().step + steps);
  sim.backend().finish();
  t.seconds = seconds_since(t0);
  t.list = sim.backend().list_stats();
  t.list_builds = t.list.builds - builds_before;
  t.steps = steps;
  for (const auto& [k, v] : sim.backend().kernel_seconds())
    t.kernel_seconds[k] = v - (kernels_before.count(k) ? kernels_before.at(k) : 0.0);
  const State& s = sim.sync();
  t.cells = s.cells();
  t.elements = s.elements();
  t.phases = sim.phases();
  if (profile_steps > 0) {
    sim.profile = true;
    const auto before = sim.phase_seconds();
    sim.advance(sim.host_state().step + profile_steps);
    for (size_t p = 0; p < before.size(); ++p)
      t.phase_seconds.push_back((sim.phase_seconds()[p] - before[p]) / profile_steps * steps);
  }
  return t;
}

CellStageTiming time_cell_stage(Scene& scene, long updates) {
  Simulation sim(scene, make_tissue(scene));
  if (!sim.has_cell_effects())
    throw InputError(scene.path +
                     ": field 'effects': the scene lists no cell effect (growth, division, differentiation)");
  sim.update_cells();  // untimed: first allocations
  const auto before = sim.cell_stage_seconds();
  for (long u = 0; u < updates; ++u) sim.update_cells();
  const State& s = sim.sync();
  CellStageTiming t{
      s.cells(), s.elements(), updates, sim.backend().name(), sim.backend().device_name(), sim.cell_stage_seconds()};
  for (size_t p = 0; p < t.parts.size(); ++p)
    t.parts[p].second = (t.parts[p].second - before[p].second) / static_cast<double>(updates);
  return t;
}

}  // namespace semlb::engine
