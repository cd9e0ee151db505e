// Backends evaluate the element kernels (pair forces, element terms, integration, noise) on one device;
// they register by name (serial, cpu-binned, opencl-allpairs, opencl-binned).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "physics/cpu_physics.hpp"
#include "common/registry.hpp"
#include "model/slices.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

// The scene's cell effects as one set of rules (physics/cells.h): growth and division (fate rules: fates/fate.hpp).
using CellRules = cellrules::semlb_cell_rules;

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

// A run-time failure inside a kernel: the first step at which it happened, the lowest element index
// that failed then, and what went wrong.
struct Failure {
  long step = -1;
  long element = -1;
  int code =
      0;  // 1: position not finite, 2: displacement above the limit, 3: force sums may leave int64 (pair_force.h)
  bool failed() const { return step >= 0; }
  std::string quantity() const;
};

// Elements of other ranks within reach of this rank's elements: they exert forces but are not moved.
struct Ghosts {
  std::vector<double> position;  // 3 per element
  std::vector<int> info;         // semlb_info_pack(cell index, counted after the owned cells, type)
  std::vector<uint64_t> keys;
  long elements() const { return static_cast<long>(keys.size()); }
};

// Bytes copied between host and device, per phase of the run (Backend::traffic).
struct Traffic {
  long h2d = 0, d2h = 0;
};

// One pair term's forces (Backend::pair_forces_local/nonlocal): the registered term's name (pairs/pair_term.hpp),
// its derived parameters (at most kMaxPluginParams reals, PairTerm::read) and the cutoff in um.
struct PairForces {
  std::string term;
  std::vector<double> params;
  double cutoff = 0;
};

// What opencl-binned's neighbour list did since construction (Backend::list_stats; semlb bench engine prints it).
struct ListStats {
  double skin = 0;        // um; 0: no list (backends without one, or the stencil over fresh bins every step)
  long builds = 0;        // list builds (the device decides them; read back from it)
  long max_partners = 0;  // the most partners one element had at a build (within cutoff + skin)
  long kmax = 0;          // partners stored per element; an element with more takes the stencil
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;
  virtual std::string device_name() const = 0;
  // Element data (positions, packed info, keys) from the host state; call after every host change.
  // Drops the ghosts.
  virtual void upload(const State& state) = 0;
  // Replaces the ghost elements (kept after the owned ones); the non-local forces come from them. The forces
  // added so far stay: a decomposed step sets the ghosts between the local and the non-local forces.
  virtual void set_ghosts(const Ghosts& ghosts) = 0;
  // The owned elements' positions; after a cell stage on the device also the cells (ids, types, counts)
  // and the per-cell fields `state` lists (of those uploaded: the device keeps the uploaded state's fields).
  virtual void download(State& state) = 0;
  // One cell stage (run_cell_stage's rules, `step` keys the newborns); the ghosts stay. C++ backends run the host
  // reference on `host` (positions downloaded first) and upload; OpenCL runs it on the device and leaves `host` stale
  // until download. Returns true when elements were added or cells divided (the grid may need refitting).
  virtual bool update_cells(State& host, const CellRules& rules, uint64_t seed, double elapsed_h, long step) = 0;
  // InputError when this backend cannot run the cell stage (an OpenCL device without double precision).
  virtual void require_cells() {}
  // The owned elements' bounding box over finite coordinates ({lo, hi}; zeros when there are none).
  virtual std::array<std::array<double, 3>, 2> bounds() = 0;
  // The ghost exchange without a full download: the owned elements' x range ({+inf, -inf} when there are
  // none), and both bands in one selection: `down` the owned elements with x < below (for the rank below; -inf:
  // none), `up` those with x > above (for the rank above; +inf: none), each in owned order, as Ghosts whose info
  // holds only the type (the receiver numbers the cells). OpenCL: flags, one scan and a gather on the device,
  // then two blocking reads (the counts; the bands into pinned host memory).
  // The union of the two bands stays on the backend as the non-local forces' items (pair_forces_nonlocal) until
  // the owned elements move or change (integrate, upload, cell stage, migration).
  virtual std::array<double, 2> x_extent() = 0;
  virtual void bands(double below, double above, Ghosts& down, Ghosts& up) = 0;
  // Owned cells and elements now (on the device for OpenCL: no download); `host` is the caller's State.
  virtual std::pair<long, long> counts(const State& host) const { return {host.cells(), host.elements()}; }
  // W_s of the owned cells on the tissue-wide grid `g` (work_grid): the owned elements counted per bin, `reduce`
  // (when given) sums the counts over the ranks, then the owned cells' w_i go into their slices. OpenCL with fp64: the
  // counts and the sums on the device (64-bit integer atomics: exact, order-free); 4 bytes per bin cross to the host
  // and back only when `reduce` is given, then 8 bytes per slice come back. Others (and OpenCL without fp64): download
  // into `host`, then bin_counts and cell_work on the host.
  virtual std::vector<double> slice_work(State& host, const SliceMap& map, const Grid& g, const CountReduce& reduce);
  // Cells whose centroid's slice is owned (owner_of) by another rank than `rank` leave: they are removed from
  // the backend (the rest keep their order) and returned in `leavers` (ids, types, counts, positions, the fields
  // `host` lists), with `owner[c]` per leaver. Drops the ghosts. OpenCL with fp64: owners and the packing on the
  // device (the leaver count, then only the leavers, come back). Others: on `host` (downloaded first), uploaded.
  virtual void take_leavers(State& host, const SliceMap& map, const std::vector<int>& boundaries, int rank,
                            State& leavers, std::vector<int>& owner);
  // Removes the owned cells that the removal rule `rule` (removal/removal.hpp) flags from their centroid, type and
  // element count, `params` its derived parameters; the others keep their order (reindexed), ids are never reused
  // (state.hpp). Drops the ghosts. Returns the number of cells removed. OpenCL with fp64: the rule's kernel and the
  // migration's compaction on the device (4 bytes back). Others: on `host` (downloaded first), then uploaded.
  // std::logic_error for an unregistered rule.
  virtual long remove_cells(State& host, const std::string& rule, const std::vector<double>& params);
  // Applies the fate rule `rule` (fates/fate.hpp) to every owned cell: its type and its per-cell field (record index
  // `field` of host's cell_fields in name order, -1: none) from its centroid, element count and `elapsed_h` h, with
  // `params` its derived parameters; elements keep their order and positions. OpenCL with fp64: the rule's kernel
  // `fate_NAME` on the device (nothing comes back). Others: on `host` (downloaded first), then uploaded (the ghosts
  // go). std::logic_error for an unregistered rule.
  virtual void cell_fate(State& host, const std::string& rule, const std::vector<double>& params, int field,
                         double elapsed_h);
  // Appends `arrivals`' cells after the owned ones (their fields by name; missing ones are 0). Drops the ghosts.
  virtual void append_cells(State& host, const State& arrivals);
  // Forces start at zero each step; the pair forces and element_term add to them (fixed point).
  virtual void zero_forces() = 0;
  // Pair forces in two parts, as GROMACS splits them: the local part (owned elements on owned elements) needs no
  // ghost, so a decomposed run computes it while the ghost bands travel; the non-local part (ghosts on owned
  // elements; nothing without ghosts, no launch) after they arrived. Each pair's force is a fixed-point integer,
  // so local + non-local equals the full sum bit for bit, in any order. `f`: the registered pair term's name, its
  // derived parameters and the cutoff in um (pairs/pair_term.hpp; std::logic_error for an unregistered term; OpenCL
  // rebuilds its program when the term is not the one it was built for); `grid` bins both parts (binned backends: the
  // ghosts in bins of their own). The non-local part visits only the owned elements of the last bands() selection when
  // one is current (kernel "forces_nonlocal"; OpenCL items = the two bands' sizes, an element in both idling in its
  // second slot; C++ the union), else every owned element. The selection is exact when every ghost lies at
  // x <= below - cutoff or x >= above + cutoff (the decomposed run's bands reach beyond the cutoff): an owned
  // element outside both bands then has no ghost within the cutoff.
  virtual void pair_forces_local(const PairForces& f, const Grid& grid) = 0;
  virtual void pair_forces_nonlocal(const PairForces& f, const Grid& grid) = 0;
  // Both parts: every pair within the cutoff (one device, tests and benches).
  void pair_forces(const PairForces& f, const Grid& grid) {
    pair_forces_local(f, grid);
    pair_forces_nonlocal(f, grid);
  }
  // Adds the registered element term `name`'s force (terms/term.hpp) on every owned element, in fixed point;
  // `params` its derived parameters (ElementTerm::read). C++ backends call the term's evaluator in their
  // precision; OpenCL launches the term's kernel (named `name`). std::logic_error for an unregistered name.
  virtual void element_term(const std::string& name, const std::vector<double>& params) = 0;
  // Y += dt/eta * F; records a Failure on a non-finite position or a step above max_step. The failing step
  // completes on every element; from the next step on, integrate and noise move nothing (frozen).
  virtual void integrate(double dt_over_eta, double max_step, long step) = 0;
  virtual void noise(double amplitude, uint64_t seed, long step) = 0;  // Y += amplitude * N(0,1)
  virtual Failure failure() = 0;
  virtual void finish() {}  // waits for queued work (so that wall times are honest)
  // The neighbour list's figures (a blocking read of 8 bytes on OpenCL); zeros without a list.
  virtual ListStats list_stats() { return {}; }
  // The owned elements' force sums now (3 per element, fixed point, 2^-32 force units), as zero_forces and the
  // force effects left them: a blocking download for tests.
  virtual std::vector<int64_t> fixed_forces() = 0;
  // finish(), calling `progress` repeatedly while the device still works (a decomposed run lets MPI move the
  // ghost bands meanwhile). The C++ backends' work is done when their calls return: progress runs once.
  virtual void finish_while(const std::function<void()>& progress) {
    progress();
    finish();
  }
  // Kernel launches by name since construction: an effect that is not listed launches none. OpenCL: every
  // kernel of kernels.cl enqueued, and "zero_forces" (a buffer fill); the C++ backends count their loops under
  // the name of the kernel that does the same work ("bin_sort" for cpu-binned's whole counting sort).
  const std::map<std::string, long>& launches() const { return launches_; }
  // Work items by kernel name since construction, summed over launches: OpenCL the items asked for (before
  // rounding up to the work-group size); the C++ backends the elements their pair-force loops visit.
  const std::map<std::string, long>& launch_items() const { return launch_items_; }
  // Device time per kernel when the backend profiles (OpenCL with SEMLB_OPENCL_PROFILE set); else empty.
  const std::map<std::string, double>& kernel_seconds() const { return kernel_seconds_; }
  // Device timers (BackendConfig::device_timing; docs/measured_time.md): the device execution seconds of the kernels
  // and fills enqueued while the phase is one of the step's (is_step_phase: forces, terms, integration, list builds,
  // the cell stage), from profiling events (nanosecond resolution), summed since construction; by kernel name in
  // step_kernel_seconds(). Events are read at finish() (or here, waiting for them). A backend without device timers
  // (the C++ backends: has_device_timers() false) reports 0 and an empty map.
  virtual bool has_device_timers() const { return false; }
  double step_device_seconds() {
    settle_timers();
    return step_device_s_;
  }
  const std::map<std::string, double>& step_kernel_seconds() {
    settle_timers();
    return step_kernel_s_;
  }
  static bool is_step_phase(const std::string& phase) { return phase == "step" || phase == "cells"; }
  // The device timers' seconds of `kernels` (step_kernel_seconds, or a difference of two) by part of the step
  // (rank_times.csv's device_*_s): the local pair forces (is_pair_force_kernel), the neighbour list's builds (keys
  // "list:NAME", the gated sort and build: their launches cost a little at every step), the cell stage (keys
  // "cells:NAME"). The rest (terms, integration, the ghosts' forces, the list's check) is none of them.
  struct DeviceParts {
    double pair = 0, list = 0, cells = 0;  // seconds
  };
  static DeviceParts device_parts(const std::map<std::string, double>& kernels);
  // Whether a kernel (by name) computes the local pair forces: those pair_force_seconds times per region.
  static bool is_pair_force_kernel(const std::string& name);
  // The measured device cost of regions of the tissue (docs/measured_time.md "Measured workloads"): `group[i]` is
  // owned element i's region (0 .. groups-1; -1: none). Returns [groups] the device seconds of the last step's local
  // pair forces (the same kernel, bins or neighbour list) restricted to each region's elements, one timed launch per
  // region into a scratch buffer: the state and its forces are unchanged. Empty when the backend has no device timers
  // or has not computed pair forces yet. std::invalid_argument when group.size() is not the owned element count.
  virtual std::vector<double> pair_force_seconds(const std::vector<int>& group, int groups) {
    (void)group, (void)groups;
    return {};
  }
  // Where the backend's device is, for ranks that take turns on it (simulation/device_turns.hpp): "PLATFORM#INDEX" for
  // an OpenCL device; empty for the C++ backends (no device to share).
  virtual std::string device_key() const { return ""; }
  // Bytes moved host<->device since construction, per phase (set_phase names it; "other" before the first).
  // OpenCL: every clEnqueueRead/WriteBuffer it does. The C++ backends hold the state in host memory: they
  // count nothing (their upload/download are copies between two host arrays).
  const std::map<std::string, Traffic>& traffic() const { return traffic_; }
  Traffic traffic_total() const;
  void set_phase(std::string phase) { phase_ = std::move(phase); }
  const std::string& phase() const { return phase_; }

 protected:
  std::map<std::string, double> kernel_seconds_;
  virtual void settle_timers() {}  // reads the device timers' pending events into the sums below
  double step_device_s_ = 0;
  std::map<std::string, double> step_kernel_s_;
  void count(const std::string& kernel, long items = 0) {
    ++launches_[kernel];
    if (items) launch_items_[kernel] += items;
  }
  std::map<std::string, long> launches_, launch_items_;
  void moved(long h2d, long d2h) {
    Traffic& t = traffic_[phase_];
    t.h2d += h2d;
    t.d2h += d2h;
  }

 private:
  std::map<std::string, Traffic> traffic_;
  std::string phase_ = "other";
};

// Names the backend's phase (Backend::set_phase) for the lifetime of the guard, then restores the previous one.
class PhaseScope {
 public:
  PhaseScope(Backend& b, const std::string& phase) : b_(b), before_(b.phase()) { b.set_phase(phase); }
  ~PhaseScope() { b_.set_phase(before_); }
  PhaseScope(const PhaseScope&) = delete;
  PhaseScope& operator=(const PhaseScope&) = delete;

 private:
  Backend& b_;
  std::string before_;
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
};
using Backends = PluginKind<BackendInfo>;
// `config` with its backend's settings read from config.settings (the scene's `backend` map; a null one: `config` as
// it is): first each registered backend NAME's own map `backend.NAME` that the scene has, read by NAME (the chosen
// one's into the result, another's only checked), then the map's keys beside name, precision and those maps, read by
// the chosen backend (they override its map: the flags --platform and --device, --set backend.KEY). Every key a
// backend does not read is an InputError naming the file, line and field ("backend 'cpu-binned' does not use it");
// an unknown backend is one naming the known ones.
BackendConfig backend_settings(const BackendConfig& config);
std::unique_ptr<Backend> make_backend(const BackendConfig& config);  // backend_settings, then the backend's factory

}  // namespace semlb::engine
