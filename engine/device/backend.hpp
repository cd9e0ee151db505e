// What a device implements to run the engine: the Backend interface in five parts (memory and state, forces, cell
// stage, halo and migration, instrumentation), each of them small enough to implement and test on its own, and the
// types they exchange. The implementations and their registry are in backends/.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/scene.hpp"
#include "model/slices.hpp"
#include "model/state.hpp"
#include "physics/cpu_physics.hpp"

namespace semlb::engine {

// The scene's cell effects as one set of rules (physics/cells.h): growth and division (fate rules: fates/fate.hpp).
using CellRules = cellrules::semlb_cell_rules;

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

// The evaluator `f` of a call below (PairForces, ElementTermCall, RemovalCall, FateCall) for a C++ backend to run;
// std::logic_error "KIND 'NAME' handed to the backend without its evaluator" for a call made by hand without one.
template <class F>
F evaluator_of(F f, const char* kind, const std::string& name) {
  if (!f) throw std::logic_error(std::string(kind) + " '" + name + "' handed to the backend without its evaluator");
  return f;
}

// Bytes copied between host and device, per phase of the run (Backend::traffic).
struct Traffic {
  long h2d = 0, d2h = 0;
};

// What the backend runs for a plug-in, handed over by the plug-in's effect (which looked its registry entry up once,
// when it was made): the plug-in's name (what the OpenCL backends build or launch: the program's pair term, the kernel
// NAME, remove_NAME or fate_NAME), its C++ evaluator (what the C++ backends call; null in a call made by hand:
// std::logic_error there) and its derived parameters (at most kMaxPluginParams reals).

// The force on element i from element j added to acc[0..2] in fixed point (pairs/pair_force.h: semlb_pair_force,
// with the coincident fallback): d = Y_i - Y_j (um), the elements' packed infos and keys, `p` the term's derived
// parameters, cutoff2 the squared cutoff (um^2). The C++ instantiation of one term in one precision
// (pairs/instantiate.hpp).
template <class Real>
using PairEvaluator = void (*)(Real dx, Real dy, Real dz, int info_i, int info_j, uint64_t key_i, uint64_t key_j,
                               const Real* p, Real cutoff2, int64_t* acc);
// One pair term's forces (ForceKernels::pair_forces_local/nonlocal; made by pairs/pair_term.hpp pair_forces_of):
// the registered term's name, its evaluator in each precision, its derived parameters and the cutoff in um.
struct PairForces {
  std::string term;
  std::vector<double> params;
  double cutoff = 0;
  PairEvaluator<double> f64 = nullptr;
  PairEvaluator<float> f32 = nullptr;
};

// The force (force units, before the fixed-point clamp) on one element at (x, y, z) um of cell type `type`,
// written into f[0..2]; `p` the term's derived parameters (ElementTerm::read). The C++ instantiation of the
// evaluator `semlb_term_NAME` of terms/NAME.h in one precision.
template <class Real>
using TermEvaluator = void (*)(Real x, Real y, Real z, int type, const Real* p, Real* f);
// One element term (ForceKernels::element_term; made by terms/term.hpp element_term_call).
struct ElementTermCall {
  std::string name;
  std::vector<double> params;
  TermEvaluator<double> f64 = nullptr;
  TermEvaluator<float> f32 = nullptr;
};

// 1 when the cell with centroid (cx, cy, cz) um, cell type `type` and `count` elements is removed; `p` the rule's
// derived parameters (RemovalRule::read). The C++ instantiation of `semlb_remove_NAME` of removal/NAME.h (double:
// the cell stage's bookkeeping is double on every backend, cells.h).
using RemovalEvaluator = int (*)(double cx, double cy, double cz, int type, int count, const double* p);
// One removal rule (CellStage::remove_cells; made by removal/removal.hpp removal_call).
struct RemovalCall {
  std::string rule;
  std::vector<double> params;
  RemovalEvaluator removes = nullptr;
};

// The fate of one cell: centroid (cx, cy, cz) um, `count` elements, `elapsed` h since the last stage, `p` the rule's
// derived parameters (FateRule::read); `type` (in/out) its cell type, `field` (in/out) its per-cell field (0 and
// discarded when the rule has none). Returns 1 when the type changed. The C++ instantiation of `semlb_fate_NAME` of
// fates/NAME.h (double: the cell stage's bookkeeping is double on every backend, cells.h).
using FateEvaluator = int (*)(double cx, double cy, double cz, int count, double elapsed, const double* p, int* type,
                              double* field);
// One fate rule (CellStage::cell_fate; made by fates/fate.hpp fate_call).
struct FateCall {
  std::string rule;
  std::vector<double> params;
  FateEvaluator decides = nullptr;
};

// What opencl-binned's neighbour list did since construction (Backend::list_stats; semlb bench engine prints it).
struct ListStats {
  double skin = 0;        // um; 0: no list (backends without one, or the stencil over fresh bins every step)
  long builds = 0;        // list builds (the device decides them; read back from it)
  long max_partners = 0;  // the most partners one element had at a build (within cutoff + skin)
  long kmax = 0;          // partners stored per element; an element with more takes the stencil
  bool newton = false;    // a half list: each pair listed once, its force added to both (max_partners counts it once)
  int bin_divisions = 1;  // the list's bins of edge (cutoff + skin) / bin_divisions
};

// Part 1, memory and state: the device's copy of the owned elements (and cells), moved to and from the host State.
class DeviceMemory {
 public:
  virtual ~DeviceMemory() = default;
  virtual std::string name() const = 0;
  virtual std::string device_name() const = 0;
  // Where the backend's device is, for ranks that take turns on it (simulation/device_turns.hpp): "PLATFORM#INDEX" for
  // an OpenCL device; empty for the C++ backends (no device to share).
  virtual std::string device_key() const { return ""; }
  // Element data (positions, packed info, keys) from the host state; call after every host change.
  // Drops the ghosts.
  virtual void upload(const State& state) = 0;
  // The owned elements' positions; after a cell stage on the device also the cells (ids, types, counts)
  // and the per-cell fields `state` lists (of those uploaded: the device keeps the uploaded state's fields).
  virtual void download(State& state) = 0;
  // Owned cells and elements now (on the device for OpenCL: no download); `host` is the caller's State.
  virtual std::pair<long, long> counts(const State& host) const { return {host.cells(), host.elements()}; }
  // The owned elements' bounding box over finite coordinates ({lo, hi}; zeros when there are none).
  virtual std::array<std::array<double, 3>, 2> bounds() = 0;
  // The owned elements' force sums now (3 per element, fixed point, 2^-32 force units), as zero_forces and the
  // force effects left them: a blocking download for tests.
  virtual std::vector<int64_t> fixed_forces() = 0;
  virtual Failure failure() = 0;
  virtual void finish() {}  // waits for queued work (so that wall times are honest)
  // finish(), calling `progress` repeatedly while the device still works (a decomposed run lets MPI move the
  // ghost bands meanwhile). The C++ backends' work is done when their calls return: progress runs once.
  virtual void finish_while(const std::function<void()>& progress) {
    progress();
    finish();
  }
};

// Part 2, forces: the element stage's kernels, all adding to one fixed-point force sum per element (what the
// effects' element parts call: effects/effect.hpp).
class ForceKernels {
 public:
  virtual ~ForceKernels() = default;
  // Forces start at zero each step; the pair forces and element_term add to them (fixed point).
  virtual void zero_forces() = 0;
  // Pair forces in two parts, as GROMACS splits them: the local part (owned elements on owned elements) needs no
  // ghost, so a decomposed run computes it while the ghost bands travel; the non-local part (ghosts on owned
  // elements; nothing without ghosts, no launch) after they arrived. Each pair's force is a fixed-point integer,
  // so local + non-local equals the full sum bit for bit, in any order. `f`: the registered pair term's name, its
  // evaluators, derived parameters and the cutoff in um (PairForces; OpenCL rebuilds its program when the term is
  // not the one it was built for); `grid` bins both parts (binned backends: the
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
  // Adds the element term `t`'s force (terms/term.hpp) on every owned element, in fixed point, with its derived
  // parameters. C++ backends call its evaluator in their precision; OpenCL launches the term's kernel (t.name).
  virtual void element_term(const ElementTermCall& t) = 0;
  // Y += dt/eta * F; records a Failure on a non-finite position or a step above max_step. The failing step
  // completes on every element; from the next step on, integrate and noise move nothing (frozen).
  virtual void integrate(double dt_over_eta, double max_step, long step) = 0;
  virtual void noise(double amplitude, uint64_t seed, long step) = 0;  // Y += amplitude * N(0,1)
  // The neighbour list's figures (a blocking read of 8 bytes on OpenCL); zeros without a list.
  virtual ListStats list_stats() { return {}; }
};

// Part 3, the cell stage: growth and division, and the cell effects' own kernels (removal, fates), on the owned
// cells (what the effects' cell parts call).
class CellStage {
 public:
  virtual ~CellStage() = default;
  // One cell stage (run_cell_stage's rules, `step` keys the newborns); the ghosts stay. C++ backends run the host
  // reference on `host` (positions downloaded first) and upload; OpenCL runs it on the device and leaves `host` stale
  // until download. Returns true when elements were added or cells divided (the grid may need refitting).
  virtual bool update_cells(State& host, const CellRules& rules, uint64_t seed, double elapsed_h, long step) = 0;
  // InputError when this backend cannot run the cell stage (an OpenCL device without double precision).
  virtual void require_cells() {}
  // Removes the owned cells that the removal rule `r` (removal/removal.hpp) flags from their centroid, type and
  // element count; the others keep their order (reindexed), ids are never reused (state.hpp). Drops the ghosts.
  // Returns the number of cells removed. OpenCL with fp64: the rule's kernel remove_NAME and the migration's
  // compaction on the device (4 bytes back). Others: its evaluator on `host` (downloaded first), then uploaded.
  virtual long remove_cells(State& host, const RemovalCall& r) = 0;
  // Applies the fate rule `r` (fates/fate.hpp) to every owned cell: its type and its per-cell field (record index
  // `field` of host's cell_fields in name order, -1: none) from its centroid, element count and `elapsed_h` h;
  // elements keep their order and positions. OpenCL with fp64: the rule's kernel fate_NAME on the device (nothing
  // comes back). Others: its evaluator on `host` (downloaded first), then uploaded (the ghosts go).
  virtual void cell_fate(State& host, const FateCall& r, int field, double elapsed_h) = 0;
};

// Part 4, halo and migration: what the decomposed run (decomposition/distributed.hpp) exchanges with the other
// ranks: the ghost bands, the per-slice work W_s, the cells that leave and arrive.
class Halo {
 public:
  virtual ~Halo() = default;
  // Replaces the ghost elements (kept after the owned ones); the non-local forces come from them. The forces
  // added so far stay: a decomposed step sets the ghosts between the local and the non-local forces.
  virtual void set_ghosts(const Ghosts& ghosts) = 0;
  // The ghost exchange without a full download: the owned elements' x range ({+inf, -inf} when there are
  // none), and both bands in one selection: `down` the owned elements with x < below (for the rank below; -inf:
  // none), `up` those with x > above (for the rank above; +inf: none), each in owned order, as Ghosts whose info
  // holds only the type (the receiver numbers the cells). OpenCL: flags, one scan and a gather on the device,
  // then two blocking reads (the counts; the bands into pinned host memory).
  // The union of the two bands stays on the backend as the non-local forces' items (pair_forces_nonlocal) until
  // the owned elements move or change (integrate, upload, cell stage, migration).
  virtual std::array<double, 2> x_extent() = 0;
  virtual void bands(double below, double above, Ghosts& down, Ghosts& up) = 0;
  // W_s of the owned cells on the tissue-wide grid `g` (work_grid): the owned elements counted per bin, `reduce`
  // (when given) sums the counts over the ranks, then the owned cells' w_i go into their slices. OpenCL with fp64: the
  // counts and the sums on the device (64-bit integer atomics: exact, order-free); 4 bytes per bin cross to the host
  // and back only when `reduce` is given, then 8 bytes per slice come back. Others (and OpenCL without fp64): download
  // into `host`, then bin_counts and cell_work on the host.
  virtual std::vector<double> slice_work(State& host, const SliceMap& map, const Grid& g,
                                         const CountReduce& reduce) = 0;
  // Cells whose centroid's slice is owned (owner_of) by another rank than `rank` leave: they are removed from
  // the backend (the rest keep their order) and returned in `leavers` (ids, types, counts, positions, the fields
  // `host` lists), with `owner[c]` per leaver. Drops the ghosts. OpenCL with fp64: owners and the packing on the
  // device (the leaver count, then only the leavers, come back). Others: on `host` (downloaded first), uploaded.
  virtual void take_leavers(State& host, const SliceMap& map, const std::vector<int>& boundaries, int rank,
                            State& leavers, std::vector<int>& owner) = 0;
  // Appends `arrivals`' cells after the owned ones (their fields by name; missing ones are 0). Drops the ghosts.
  virtual void append_cells(State& host, const State& arrivals) = 0;
};

// Which slices held an element that had moved past the neighbour list's displacement trigger at each build of a
// span of steps (Instruments::take_list_triggers; docs/measured_time.md "List triggers").
struct ListTriggers {
  long builds = 0;              // list builds in the span, whatever started them (a trigger, the host, a cell stage)
  std::vector<int64_t> slices;  // [slices] bit j: set at the span's j-th build (31st and later: bit 30); empty: none
};

// Part 5, instrumentation: what the backend counts and times (launches, host<->device bytes per phase, device
// timers); the counters are kept here, the backends add to them.
class Instruments {
 public:
  virtual ~Instruments() = default;
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
  // A recording's list triggers (WorkloadEvent::list_triggers): from now on the backend marks, at each neighbour-list
  // build, the slices along x (slice k: [x0_um + k width_um, x0_um + (k + 1) width_um), `slices` of them, an x
  // outside clamped) that held an owned element past the list's displacement trigger; take_list_triggers returns the
  // span since the last take (or since tracking began) and starts the next. A backend without a list (all but
  // opencl-binned with a skin) tracks nothing and takes {0, {}}.
  virtual void track_list_triggers(double x0_um, double width_um, int slices) {
    (void)x0_um, (void)width_um, (void)slices;
  }
  virtual ListTriggers take_list_triggers() { return {}; }
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

// A backend: the element kernels of one device (serial, cpu-binned, opencl-allpairs, opencl-binned; backends/), all
// five parts in one object, since they share the device's buffers. A new device implements each part (a C++ backend
// that keeps the state in host memory takes the cell operations' host versions from backends/backend.hpp's
// HostCellOps); a caller that needs one part takes it alone (the effects take ForceKernels or CellStage).
class Backend : public DeviceMemory, public ForceKernels, public CellStage, public Halo, public Instruments {};

// Names the backend's phase (Instruments::set_phase) for the lifetime of the guard, then restores the previous one.
class PhaseScope {
 public:
  PhaseScope(Instruments& b, const std::string& phase) : b_(b), before_(b.phase()) { b.set_phase(phase); }
  ~PhaseScope() { b_.set_phase(before_); }
  PhaseScope(const PhaseScope&) = delete;
  PhaseScope& operator=(const PhaseScope&) = delete;

 private:
  Instruments& b_;
  std::string before_;
};

}  // namespace semlb::engine
