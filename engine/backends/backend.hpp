// Backends: the devices that run the engine (serial, cpu-binned, opencl-allpairs, opencl-binned), registered by name,
// with the host versions of the cell operations and the host cell stage (the reference the devices match). The
// interface they implement is device/backend.hpp.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "device/backend.hpp"
#include "model/scene.hpp"
#include "model/slices.hpp"
#include "model/state.hpp"

namespace semlb::engine {

// The cell stage on the host State (cells.cpp): the reference. Growth and division of every
// cell in stored order; new cells (daughters) after the existing ones in their mothers' order. Uses and updates
// the per-cell fields of `s` as the record the rules index (cells.h: rules.fields = s.cell_fields.size(), each rule's
// field at its index); a daughter inherits its mother's fields. std::logic_error when the record disagrees with `s`.
// Returns true when elements were added or cells divided. Throws std::runtime_error when a cell would
// divide more than kMaxDivisionDepth times.
bool run_cell_stage(State& s, const CellRules& rules, uint64_t seed, double elapsed_h, long step);
// The message of a cell that would divide a (kMaxDivisionDepth + 1)-th time at `step`: its lineage has no ids left
// (every backend throws std::runtime_error with it).
std::string ids_exhausted(uint64_t id, int depth, long step);

// A backend whose cell operations (W_s, migration, removal, fates) run on a host State: each downloads into `host`,
// works there, and uploads what changed (the C++ backends, whose state is in host memory; OpenCL without fp64).
class HostCellOps : public Backend {
 public:
  std::vector<double> slice_work(State& host, const SliceMap& map, const Grid& g, const CountReduce& reduce) override;
  void take_leavers(State& host, const SliceMap& map, const std::vector<int>& boundaries, int rank, State& leavers,
                    std::vector<int>& owner) override;
  long remove_cells(State& host, const RemovalCall& r) override;  // std::logic_error without its evaluator
  void cell_fate(State& host, const FateCall& r, int field, double elapsed_h) override;  // the same
  void append_cells(State& host, const State& arrivals) override;
};

using BackendFactory = std::function<std::unique_ptr<Backend>(const BackendConfig&)>;
// A registered backend: `const Registrar<BackendInfo> registrar("name", {factory, read});` (common/registry.hpp).
struct BackendInfo {
  static constexpr const char* kKind = "backend";
  static constexpr const char* kListed = "backends";
  BackendFactory make;
  // Reads the backend's own settings from a section of the scene's `backend` map into the config (each key with the
  // config's value as its fallback); nullptr: it has none. A key it does not read is an error (backend_settings).
  std::function<void(const Section&, BackendConfig&)> read;
  // Refuses a combination of settings once all of them are read (a key of the backend's own map may need one set
  // beside it, as `newton` needs `skin`): calls fail(KEY, WHY), which throws naming where KEY was set; nullptr: none.
  std::function<void(const BackendConfig&, const std::function<void(const std::string&, const std::string&)>& fail)>
      check;
};
using Backends = PluginKind<BackendInfo>;
// `config` with its backend's settings read from config.settings (the scene's `backend` map; a null one: `config` as
// it is): first each registered backend NAME's own map `backend.NAME` that the scene has, read by NAME (the chosen
// one's into the result, another's only checked), then the map's keys beside name, precision and those maps, read by
// the chosen backend (they override its map: the flags --platform and --device, --set backend.KEY); then each
// backend's check, on the chosen one's settings from both places (another's on its map alone). Every key a backend
// does not read, and every combination its check refuses, is an InputError naming the file, line and field
// ("backend 'cpu-binned' does not use it"); an unknown backend is one naming the known ones.
BackendConfig backend_settings(const BackendConfig& config);
std::unique_ptr<Backend> make_backend(const BackendConfig& config);  // backend_settings, then the backend's factory

}  // namespace semlb::engine
