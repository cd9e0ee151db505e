// Hand-made engine workloads shared by the replay tests (surrogate, CLI): small enough to compute by hand.
#pragma once
#include "controllers/workload.hpp"

namespace semlb::test {

// A workload without events: `slices` slices of at least `min_width` per rank, an event every `rebalance_every` steps,
// the shipped scenes' cutoff (8.75 um) and a ghost reach of 8.8 um.
inline EngineWorkload workload_shape(int slices, int min_width, int rebalance_every) {
  EngineWorkload w;
  w.slices = slices;
  w.min_width = min_width;
  w.cutoff_um = 8.75;
  w.ghost_reach_um = 8.8;
  w.rebalance_every = rebalance_every;
  return w;
}

// 4 slices of min width 1, 2 events of 8 elements (2 units of W_s per element), one ghost element at every edge each
// way: W_s = 4, 4, 4, 4 (even), then 8, 4, 2, 2 (heavy on the left).
inline EngineWorkload hand_workload() {
  EngineWorkload w = workload_shape(4, 1, 10);
  WorkloadEvent a;
  a.step = 10;
  a.elements = 8;
  a.cells = 1;
  a.interval_s = 1;
  a.slice_work = {4, 4, 4, 4};
  a.slice_elements = {2, 2, 2, 2};
  a.band_below = {1, 1, 1};
  a.band_above = {1, 1, 1};
  WorkloadEvent b = a;
  b.step = 20;
  b.slice_work = {8, 4, 2, 2};
  w.events = {a, b};
  return w;
}

}  // namespace semlb::test
