// Backends evaluate the element kernels (pair forces, membrane, integration, noise) on one device;
// they register by name (serial, cpu-binned, opencl-allpairs, opencl-binned).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "backends/cpu_physics.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

// The box that bins cover. Elements outside are clamped into the edge bins, which keeps every pair
// within the cutoff in neighbouring bins (clamping is 1-Lipschitz in bin units).
struct Grid {
  std::array<double, 3> lo{}, size{};  // bin edge length >= cutoff
  std::array<int, 3> dims{1, 1, 1};
  long bins() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
  static Grid cover(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cutoff);
  std::array<int, 3> bin_of(const double* p) const;
};

// The scene's cell effects as one set of rules (backends/cells.h): growth, division, differentiation.
using CellRules = cellrules::semlb_cell_rules;

// The cell stage on the host State (cells.cpp): the reference. Growth, division, differentiation of every
// cell in stored order; new cells (daughters) after the existing ones in their mothers' order. Uses and updates
// the cell fields "growth.clock", "division.depth", "differentiation.age" of the effects that are on.
// Returns true when elements were added or cells divided. Throws std::runtime_error when a cell would
// divide more than kMaxDivisionDepth times.
bool run_cell_stage(State& s, const CellRules& rules, uint64_t seed, double elapsed_h, long step);

// A run-time failure inside a kernel: the first step at which it happened, the lowest element index
// that failed then, and what went wrong.
struct Failure {
  long step = -1;
  long element = -1;
  int code = 0;  // 1: position not finite, 2: displacement above the limit
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

class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;
  virtual std::string device_name() const = 0;
  // Element data (positions, packed info, keys) from the host state; call after every host change.
  // Drops the ghosts.
  virtual void upload(const State& state) = 0;
  // Replaces the ghost elements (kept after the owned ones); forces on owned elements include them.
  virtual void set_ghosts(const Ghosts& ghosts) = 0;
  // The owned elements' positions; after a cell stage on the device also the cells (ids, types, counts)
  // and the cell fields the state lists ("growth.clock", "division.depth", "differentiation.age").
  virtual void download(State& state) = 0;
  // One cell stage (run_cell_stage's rules, `step` keys the newborns). C++ backends run the host reference
  // on `host` (positions downloaded first) and upload; OpenCL runs it on the device and leaves `host` stale
  // until download. Returns true when elements were added or cells divided (the grid may need refitting).
  virtual bool update_cells(State& host, const CellRules& rules, uint64_t seed, double elapsed_h, long step) = 0;
  // InputError when this backend cannot run the cell stage (an OpenCL device without double precision).
  virtual void require_cells() {}
  // The owned elements' bounding box over finite coordinates ({lo, hi}; zeros when there are none).
  virtual std::array<std::array<double, 3>, 2> bounds() = 0;
  // The ghost exchange without a full download: the owned elements' x range ({+inf, -inf} when there are
  // none), and the owned elements with x below `x` (below) or above it, in owned order, as Ghosts whose
  // info holds only the type (the receiver numbers the cells).
  virtual std::array<double, 2> x_extent() = 0;
  virtual void band(double x, bool below, Ghosts& out) = 0;
  // Forces start at zero each step; pair_forces and membrane_forces add to them (fixed point).
  virtual void zero_forces() = 0;
  virtual void pair_forces(const std::vector<double>& table, double cutoff, const Grid& grid) = 0;
  virtual void membrane_forces(const std::vector<double>& membrane) = 0;
  // Y += dt/eta * F; records a Failure on a non-finite position or a step above max_step. The failing step
  // completes on every element; from the next step on, integrate and noise move nothing (frozen).
  virtual void integrate(double dt_over_eta, double max_step, long step) = 0;
  virtual void noise(double amplitude, uint64_t seed, long step) = 0;  // Y += amplitude * N(0,1)
  virtual Failure failure() = 0;
  virtual void finish() {}  // waits for queued work (so that wall times are honest)
  // Kernel launches by name since construction: an effect that is not listed launches none. OpenCL: every
  // kernel of kernels.cl enqueued, and "zero_forces" (a buffer fill); the C++ backends count their loops under
  // the name of the kernel that does the same work ("bin_sort" for cpu-binned's whole counting sort).
  const std::map<std::string, long>& launches() const { return launches_; }
  // Device time per kernel when the backend profiles (OpenCL with SEMLB_OPENCL_PROFILE set); else empty.
  const std::map<std::string, double>& kernel_seconds() const { return kernel_seconds_; }

 protected:
  std::map<std::string, double> kernel_seconds_;
  void count(const std::string& kernel) { ++launches_[kernel]; }
  std::map<std::string, long> launches_;
};

using BackendFactory = std::function<std::unique_ptr<Backend>(const BackendConfig&)>;
struct BackendRegistrar {
  BackendRegistrar(const std::string& name, BackendFactory factory);
};
std::unique_ptr<Backend> make_backend(const BackendConfig& config);  // InputError names the known ones
std::vector<std::string> backend_names();

}  // namespace semlb::engine
