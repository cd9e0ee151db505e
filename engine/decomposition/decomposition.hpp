// The slab decomposition along x (paper Sec. III-D): slices, the minimum slab width, the per-slice workload
// W_s and the ownership rule; parsed and checked from a scene's `decomposition` section.
#pragma once
#include <string>
#include <vector>

#include "controllers/policy.hpp"
#include "model/scene.hpp"
#include "backends/backend.hpp"
#include "model/state.hpp"

namespace semlb::engine {

struct Decomposition : SliceMap {
  // min_width in slices: on 3 or more ranks at least the ghost region, cutoff + a cell's reach (one cutoff)
  // on either side, so that only neighbouring ranks share elements within the cutoff (docs/engine.md)
  int min_width = 1;  // slices, x0, width: SliceMap (backends/backend.hpp)
  std::string policy = "reactive", initial = "workload";
  // measured: each rank's computation time from its clock; modelled: its share of the workload W_s (work
  // units), so that decisions are the same in every launch (tests, studies that need reproducible decisions);
  // device: the device execution time of its step kernels (Backend::step_device_seconds; OpenCL backends only)
  std::string timing = "measured";
  // none: each rank has its device; turns: ranks on one device take turns for their device work
  // (simulation/device_turns.hpp), so that device timers measure each rank as if it had the device alone (OpenCL
  // backends; overlap off)
  std::string device_sharing = "none";
  long rebalance_every = 100;
  // true: the ghost bands travel while the device computes the local forces (MPI_Isend/Irecv posted after the
  // local kernel is enqueued, polled during it); false: the exchange completes before any force (blocking), for
  // timing the two against each other. The result is the same bit for bit.
  bool overlap = true;
  PolicyParams params;

  // InputError names the field: slab widths below the ghost region on >= 3 ranks, more ranks than the
  // slices hold, a policy that needs what the engine cannot observe (e.g. the oracle's true work).
  static Decomposition from_scene(const Scene& scene, int ranks);
};

// Throws InputError (the reason, no location) for a policy a simulation cannot run: an unknown name, or one
// that needs what the engine cannot measure (PolicyNeeds::true_work: the oracles' work of the next interval).
// Decomposition::from_scene and the sweep's engine runners (before anything runs) both refuse through it.
void check_engine_policy(const std::string& policy);

// SliceMap, owner_of, split_by_owner and slice_workload (W_s): model/slices.hpp.

}  // namespace semlb::engine
