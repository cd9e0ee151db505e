// HDF5 states (snapshots, checkpoints, final.h5) and the XDMF index that opens them in ParaView.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <optional>

#include "controllers/balancer.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

// A decomposed run's balancer as saved in its checkpoints (group /decomposition, format version
// kBalancerStateVersion): the rank count, slice count, min width and policy it belongs to, the cell count at the last
// rebalancing event (for the next event's growth flag), the x range the slices divide (um; a restart keeps it, so that
// slice indices keep their meaning) and the Balancer's state (boundaries, event index, migration, the
// policy's history as /decomposition/policy/NAME arrays).
struct DecompositionCheckpoint {
  std::string file;                          // where it was read from (messages)
  int ranks = 0, slices = 0, min_width = 1;  // the partition model it belongs to
  std::string policy;
  long cells_at_event = 0;
  double x_lo = 0, x_hi = 0;
  BalancerState balancer;
};

// Writes PATH atomically (PATH.tmp, then rename): /elements/{position,cell,type,slot,vertex} (slot: the element's
// index in its cell; vertex: 0..n-1, the connectivity the XDMF index points at), /cells/{id,type,count},
// /cells/fields/NAME, root attributes step, time and the given text attributes, and `decomposition` if given.
void write_state(const std::string& path, const State& state, const std::map<std::string, std::string>& attributes,
                 const DecompositionCheckpoint* decomposition = nullptr);
// The /decomposition group of a state file, if it has one; InputError names the file and dataset.
std::optional<DecompositionCheckpoint> read_decomposition(const std::string& path);
// Reads and validates a state file; InputError names the file and the dataset.
State read_state(const std::string& path);
// The initial tissue of `scene` (model/tissue.hpp), a `tissue.file` read by read_state. Throws InputError.
State make_tissue(Scene& scene);

struct Snapshot {
  long step;
  double time;
  long elements;
  std::string file;  // relative to the XDMF file
};
// Writes PATH atomically: an XDMF 3 temporal collection with one grid per state file (written by write_state):
// one Polyvertex cell per element (connectivity /elements/vertex), positions, and the cell id, type and slot
// as point data. ParaView's default reader (Xdmf3) opens it. A single state gets a collection of one.
void write_xdmf(const std::string& path, const std::vector<Snapshot>& snapshots);

}  // namespace semlb::engine
