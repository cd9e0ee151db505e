// HDF5 states (snapshots, checkpoints, final.h5) and the XDMF index that opens them in ParaView.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "state.hpp"

namespace semlb::engine {

// Writes PATH atomically (PATH.tmp, then rename): /elements/{position,cell,type}, /cells/{id,type,count},
// /cells/fields/NAME, root attributes step, time and the given text attributes.
void write_state(const std::string& path, const State& state, const std::map<std::string, std::string>& attributes);
// Reads and validates a state file; InputError names the file and the dataset.
State read_state(const std::string& path);

struct Snapshot {
  long step;
  double time;
  long elements;
  std::string file;  // relative to the XDMF file
};
// A temporal collection of polyvertex grids (positions, cell id and type per element).
void write_xdmf(const std::string& path, const std::vector<Snapshot>& snapshots);

}  // namespace semlb::engine
