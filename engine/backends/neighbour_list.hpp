// opencl-binned's neighbour list with a skin, reused across steps (the host side of neighbour_list.cl).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "backend.hpp"
#include "opencl.hpp"

namespace semlb::engine {

// A Verlet list over the owned elements of one OpenCL backend (HOOMD-blue's nlist with r_buff, LAMMPS's
// `neighbor SKIN bin` with `neigh_modify check yes`): built from bins of edge >= cutoff + skin, it lists per element
// the partners within cutoff + skin; the force kernel evaluates only those. The list is rebuilt on the device when an
// element has moved by more than SEMLB_NL_TRIGGER (0.49) skin since the last build (a flag raised by nl_check, read
// by the gated build kernels: no host round trip per step), and by the host whenever the owned elements change
// (upload, cell stage, migration: invalidate()), the grid or the cutoff changes, or kmax must grow. Exact: the pairs
// within the cutoff are those of all pairs, so forces are the same fixed-point sums bit for bit.
// B is the backend class (OpenClBackend<Real>): it provides buffer(), launch(), fill(), sort_into_bins().
template <class Real>
class NeighbourList {
 public:
  // newton: a half list (each pair once, the kernels built with -DSEMLB_NEWTON; needs skin > 0); split: the kernels
  // were built with -DSEMLB_NL_SPLIT (nl_overflow then visits every slot; else one item); bin_divisions: the list's
  // bins of edge (cutoff + skin) / bin_divisions (the kernels built with -DSEMLB_NL_REACH=bin_divisions when > 1).
  NeighbourList(double skin, bool newton, bool split, int bin_divisions = 1) : split_(split) {
    stats_.skin = skin;
    stats_.newton = newton && skin > 0;
    stats_.bin_divisions = skin > 0 ? bin_divisions : 1;
  }
  bool on() const { return stats_.skin > 0; }
  bool newton() const { return stats_.newton; }
  int bin_divisions() const { return stats_.bin_divisions; }
  void invalidate() { valid_ = false; }
  // The device's build count and largest partner count (a blocking read of 8 bytes: benches and tests only).
  template <class B>
  ListStats stats(B& b) {
    if (!on() || !stats_buf_) return stats_;
    cl_int s[2] = {0, 0};
    b.read(stats_buf_, s, sizeof s);
    stats_.max_partners = s[0];
    stats_.builds = s[1];
    stats_.kmax = stored_kmax_;
    return stats_;
  }

  // Marks, from now on, which slices along x (slice k: [x0 + k width, x0 + (k + 1) width) um, `slices` of them)
  // held an element past the displacement trigger at each build (Instruments::track_list_triggers).
  template <class B>
  void track_triggers(B& b, double x0, double width, int slices) {
    if (!on() || slices <= 0) return;
    x0_ = x0, width_ = width, slices_ = slices;
    moved_ = b.buffer(static_cast<size_t>(slices) * sizeof(cl_int));
    bits_ = b.buffer(static_cast<size_t>(slices) * sizeof(cl_int));
    b.fill(moved_, 0, static_cast<size_t>(slices) * sizeof(cl_int));
    b.fill(bits_, 0, static_cast<size_t>(slices) * sizeof(cl_int));
    base_ = stats(b).builds;
  }
  // The builds since the last call (or track_triggers) and, per slice, the bits of those at which one of its elements
  // had moved past the trigger (bit j: the j-th build of the span, the 31st and later sharing bit 30); then starts a
  // new span. Blocking reads of 4 bytes per slice and 8; {0, {}} when not tracking.
  template <class B>
  ListTriggers take_triggers(B& b) {
    if (slices_ <= 0) return {};
    const long builds = stats(b).builds;
    std::vector<cl_int> bits(static_cast<size_t>(slices_));
    b.read(bits_, bits.data(), bits.size() * sizeof(cl_int));
    b.fill(bits_, 0, bits.size() * sizeof(cl_int));
    ListTriggers t{builds - base_, std::vector<int64_t>(bits.begin(), bits.end())};
    base_ = builds;
    return t;
  }

  // Adds the local pair forces (the backend's owned elements [0, n), its pos_, on each other) to force and their
  // bounds to bound, as opencl-binned's stencil does.
  template <class B>
  void forces(B& b, const Grid& g, double cutoff, const cl::Mem& table, const cl::Mem& keys, const cl::Mem& force,
              const cl::Mem& bound, long n) {
    if (n <= 0) return;
    std::array<double, 3> hi{};
    for (int d = 0; d < 3; ++d) hi[d] = g.lo[d] + g.size[d] * g.dims[d];
    const Grid lg = Grid::cover(g.lo, hi, (cutoff + stats_.skin) / stats_.bin_divisions);
    poll();
    bool rebuild =
        !valid_ || n != n_ || cutoff != cutoff_ || lg.lo != grid_.lo || lg.size != grid_.size || lg.dims != grid_.dims;
    if (!gate_) {
      gate_ = b.buffer(sizeof(cl_int));
      stats_buf_ = b.buffer(2 * sizeof(cl_int));
      b.fill(stats_buf_, 0, 2 * sizeof(cl_int));
    }
    if (n > capacity_ || kmax_ > stored_kmax_) {
      allocate(b, std::max(n + n / 4 + 64, capacity_));
      rebuild = true;
    }
    grid_ = lg;
    n_ = n;
    cutoff_ = cutoff;
    const cl_int ni = static_cast<cl_int>(n), kmax = static_cast<cl_int>(stored_kmax_);
    const Real list = static_cast<Real>(cutoff + stats_.skin);
    if (rebuild) {
      b.fill(gate_, 1, sizeof(cl_int));
    } else {
      b.launch("nl_check", n, kGroup, b.pos_.get(), sort_.sorted_index.get(), ref_.get(), sort_.sorted_pos.get(), ni,
               static_cast<Real>(stats_.skin), gate_.get(), slices_ > 0 ? moved_.get() : gate_.get(),
               static_cast<Real>(x0_), static_cast<Real>(slices_ > 0 ? 1.0 / width_ : 0.0),
               static_cast<cl_int>(slices_));
    }
    // the build, gated: bins of edge >= (cutoff + skin) / bin_divisions (the backend's sort, grid-stride: a gated
    // launch costs little)
    b.set_kernel_group("list:");  // the device timers' list part (Backend::device_parts)
    b.sort_into_bins(lg, 0, n, sort_, &gate_, &ref_, kStrideItems);
    const long wide = std::min<long>(n, kStrideItems);
    const auto lo = b.real4(lg.lo), size = b.real4(lg.size);
    const auto dims = b.int4(lg.dims);
    b.launch("nl_build", wide, kGroup, gate_.get(), sort_.sorted_pos.get(), sort_.starts.get(), lo, size, dims,
             static_cast<Real>(list * list), ni, kmax, count_.get(), list_.get(), stats_buf_.get());
    b.set_kernel_group("");
    if (slices_ > 0)
      b.launch("nl_mark", slices_, kGroup, gate_.get(), stats_buf_.get(), moved_.get(), bits_.get(),
               static_cast<cl_int>(base_), static_cast<cl_int>(slices_));
    b.set_kernel_group("list:");
    b.launch("nl_done", 1, 1, gate_.get(), stats_buf_.get());
    b.set_kernel_group("");
    b.launch("nl_forces", n, kGroup, sort_.sorted_pos.get(), ref_.get(), sort_.sorted_index.get(), keys.get(),
             count_.get(), list_.get(), kmax, sort_.starts.get(), lo, size, dims, table.get(),
             static_cast<Real>(cutoff), force.get(), bound.get(), ni);
    b.launch("nl_overflow", split_ ? n : 1, kGroup, sort_.sorted_pos.get(), ref_.get(), sort_.sorted_index.get(),
             keys.get(), count_.get(), kmax, sort_.starts.get(), lo, size, dims, table.get(), static_cast<Real>(cutoff),
             force.get(), bound.get(), ni);
    valid_ = true;
    if (rebuild || ++since_read_ >= kReadEvery) request(b);  // kmax follows the densest element, a step or more late
  }

  // The list's sort as of its last build (sorted_index: slot -> element); meaningful once forces() ran (valid()).
  const cl::BinSort& sort() const { return sort_; }
  bool valid() const { return valid_; }
  // nl_forces over the sorted slots items[first, first + n) into `force` and `bound` (a region's measured cost).
  template <class B>
  void forces_items(B& b, const cl::Mem& table, const cl::Mem& keys, const cl::Mem& force, const cl::Mem& bound,
                    const cl::Mem& items, long first, long n) {
    const auto lo = b.real4(grid_.lo), size = b.real4(grid_.size);
    const auto dims = b.int4(grid_.dims);
    b.launch("nl_forces_items", n, kGroup, sort_.sorted_pos.get(), ref_.get(), sort_.sorted_index.get(), keys.get(),
             count_.get(), list_.get(), static_cast<cl_int>(stored_kmax_), sort_.starts.get(), lo, size, dims,
             table.get(), static_cast<Real>(cutoff_), force.get(), bound.get(), items.get(), static_cast<cl_int>(first),
             static_cast<cl_int>(n));
  }

 private:
  static constexpr size_t kGroup = 128;           // work-group size of the list kernels (nl_forces: NL_SORT_GROUP)
  static constexpr long kStrideItems = 1L << 18;  // work-items of the gated grid-stride kernels
  static constexpr long kReadEvery = 32;          // steps between reads of the largest partner count
  static constexpr long kWarp = 32;               // slots per block of the list (NL_WARP)
  static constexpr long kChunk = 8;               // partners per chunk (NL_CHUNK): kmax is a multiple

  template <class B>
  void allocate(B& b, long capacity) {
    capacity_ = (capacity + kWarp - 1) / kWarp * kWarp;  // whole warp blocks (neighbour_list.cl NL_AT)
    capacity = capacity_;
    const long fits = static_cast<long>(b.max_alloc() / sizeof(cl_int) / static_cast<size_t>(capacity));
    cap_ = std::max(kChunk, fits / kChunk * kChunk);
    kmax_ = (std::min(kmax_, cap_) + kChunk - 1) / kChunk * kChunk;  // one buffer holds the list; whole chunks
    stored_kmax_ = kmax_;
    count_ = b.buffer(capacity * sizeof(cl_int));
    ref_ = b.buffer(capacity * sizeof(std::array<Real, 4>));
    list_ = b.buffer(static_cast<size_t>(capacity) * static_cast<size_t>(kmax_) * sizeof(cl_int));
  }
  // A non-blocking read of the largest partner count, unless one is in flight.
  template <class B>
  void request(B& b) {
    if (pending_) return;
    since_read_ = 0;
    pending_ = b.read_event(stats_buf_, host_stats_.data(), sizeof host_stats_);
  }
  // If the last read has arrived: kmax grows to 9/8 of the largest count (+8), up to what one buffer may hold.
  void poll() {
    if (!pending_) return;
    cl_int status = CL_QUEUED;
    cl::check(clGetEventInfo(pending_.get(), CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status, nullptr),
              "clGetEventInfo");
    if (status != CL_COMPLETE) return;
    pending_ = cl::Event();
    const long most = host_stats_[0];
    if (most <= stored_kmax_ || stored_kmax_ >= cap_) return;
    kmax_ = most + most / 8 + 8;  // allocate() caps it to one buffer
  }

  ListStats stats_;
  bool split_ = false, valid_ = false;
  long n_ = -1, capacity_ = 0, kmax_ = 64, stored_kmax_ = -1, cap_ = 1L << 40, since_read_ = 0;
  double cutoff_ = -1;
  Grid grid_;
  cl::BinSort sort_;  // the build's counting sort (its sorted_pos: the positions now, in the build's order)
  cl::Mem gate_, stats_buf_, count_, ref_, list_;
  // the list triggers' slices (track_triggers): nl_check's flags, the span's bits, the build count at its start
  cl::Mem moved_, bits_;
  double x0_ = 0, width_ = 1;
  int slices_ = 0;
  long base_ = 0;
  cl::Event pending_;
  std::array<cl_int, 2> host_stats_{};
};

}  // namespace semlb::engine
