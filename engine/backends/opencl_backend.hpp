// The OpenCL backends (opencl-allpairs, opencl-binned) as one class template over the precision: declared here,
// defined in opencl_backend.cpp (device, program, element kernels, ghost bands) and opencl_cells.cpp (the cell
// stage, W_s and the migration on the device); the kernels are kernels.cl and its parts.
#pragma once
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <tuple>
#include "backend.hpp"
#include "common/errors.hpp"
#include "common/registry.hpp"
#include "physics/cpu_physics.hpp"
#include "model/tissue.hpp"
#include "neighbour_list.hpp"
#include "opencl.hpp"
#include "terms/term.hpp"

namespace semlb::engine::opencl_impl {

constexpr size_t kGroup = 128;        // work-group size of the element kernels
constexpr size_t kScanGroup = 256;    // work-group size of the bin scan
constexpr size_t kExtentGroups = 64;  // work-groups of the x range reduction

struct LocalBytes {  // a __local kernel argument
  size_t bytes;
};

inline size_t round_up(size_t n, size_t m) { return (n + m - 1) / m * m; }

// The pair force law's exp (BackendConfig::pair_exp; docs/engine.md "Pair exp") that `named` asks for, or the
// precision's default when empty: native in float (`single`), ranged in double. InputError for a name other than
// builtin, ranged or native, and for ranged in float (a double exp).
std::string pair_exp_of(const std::string& named, bool single);

template <class Real>
class OpenClBackend final : public HostCellOps {
  using Real4 = std::array<Real, 4>;

 public:
  OpenClBackend(const BackendConfig& c, bool binned);

  std::string name() const override { return binned_ ? "opencl-binned" : "opencl-allpairs"; }
  std::string device_name() const override { return dev_.platform_name + ": " + dev_.device_name; }

  void upload(const State& s) override;

  // The ghosts go up from pinned memory without a host sync (two non-blocking writes): the next call waits for
  // them before it reuses that memory.
  void set_ghosts(const Ghosts& g) override;

  std::pair<long, long> counts(const State&) const override { return {cells_, owned_}; }

  std::vector<double> slice_work(State& host, const SliceMap& map, const Grid& g, const CountReduce& reduce) override;

  void take_leavers(State& host, const SliceMap& map, const std::vector<int>& boundaries, int rank, State& leavers,
                    std::vector<int>& owner) override;

  long remove_cells(State& host, const RemovalCall& r) override;
  void cell_fate(State& host, const FateCall& r, int field, double elapsed_h) override;
  void append_cells(State& host, const State& arrivals) override;

  void download(State& s) override;

  void require_cells() override {
    if (!has_fp64_)
      throw InputError("effects: the cell stage needs double precision on the device, and '" + dev_.device_name +
                       "' has none (cl_khr_fp64); use a device with it or a C++ backend");
  }

  std::array<std::array<double, 3>, 2> bounds() override;

  // The cell stage on the device: cells_plan, scans of the new counts and of the divisions, cells_rewrite into
  // the second element and cell buffers (swapped after), cells_differentiate. Only the new element and cell
  // counts and the depth-error flag come back.
  bool update_cells(State&, const CellRules& rules, uint64_t seed, double elapsed_h, long step) override;

  std::array<double, 2> x_extent() override;

  // Flags of both bands, one scan over the 2n flags, the gather (bands and the non-local items) on the device; two
  // blocking reads: the two counts, then the bands (positions, keys) into pinned memory.
  void bands(double below, double above, Ghosts& down, Ghosts& up) override;

  void zero_forces() override {
    count("zero_forces");
    const cl_long zero = 0;
    for (auto [m, items, what] :
         {std::tuple{&force_, 3 * owned_, "zero forces"}, {&bound_, owned_, "zero force bounds"}}) {
      cl_event raw = nullptr;
      if (owned_)
        cl::check(clEnqueueFillBuffer(queue_.get(), m->get(), &zero, sizeof zero, 0, items * sizeof(cl_long), 0,
                                      nullptr, timing() ? &raw : nullptr),
                  what);
      if (raw) pending_.emplace_back(step_key("zero_forces"), cl::Event(raw));
    }
    terms_ = 0;
  }

  void pair_forces_local(const PairForces& f, const Grid& grid) override;

  // The ghosts sorted into bins of their own on the device (the same counting sort, its own buffers), then one
  // item per owned element of the bands' selection (or every owned element without one).
  void pair_forces_nonlocal(const PairForces& f, const Grid& grid) override;

  void element_term(const ElementTermCall& t) override;

  void integrate(double dt_over_eta, double max_step, long step) override {
    if (step > INT_MAX) throw std::runtime_error("opencl backends count steps in 32 bits");
    near_valid_ = false;  // the bands' selection was for these positions
    launch("integrate", owned_, kGroup, pos_.get(), force_.get(), bound_.get(),
           static_cast<cl_long>(terms_ * SEMLB_TERM_BOUND), static_cast<Real>(dt_over_eta),
           static_cast<Real>(max_step * max_step), static_cast<cl_int>(step), fail_.get(), owned());
  }

  void noise(double amplitude, uint64_t seed, long step) override {
    launch("noise", owned_, kGroup, pos_.get(), keys_.get(), static_cast<Real>(amplitude), static_cast<cl_ulong>(seed),
           static_cast<cl_long>(step), fail_.get(), owned());
  }

  Failure failure() override;

  void finish() override {
    cl::check(clFinish(queue_.get()), "clFinish");
    settle_timers();
  }
  bool has_device_timers() const override { return device_timing_; }
  std::vector<double> pair_force_seconds(const std::vector<int>& group, int groups) override;
  std::string device_key() const override { return dev_.platform_name + "#" + std::to_string(dev_.index); }
  ListStats list_stats() override { return list_.stats(*this); }
  void track_list_triggers(double x0_um, double width_um, int slices) override {
    list_.track_triggers(*this, x0_um, width_um, slices);
  }
  ListTriggers take_list_triggers() override { return list_.take_triggers(*this); }
  std::vector<int64_t> fixed_forces() override {
    std::vector<int64_t> f(3 * owned_);
    read(force_, f.data(), f.size() * sizeof(int64_t));
    return f;
  }

  void finish_while(const std::function<void()>& progress) override;

  // The options the program was last built with (-D...: precision, half list, pair exp, pair term, build_options()).
  const std::string& program_options() const { return options_; }

 private:
  cl_int owned() const { return static_cast<cl_int>(owned_); }

  void write_elements(long at, const std::vector<double>& position, const std::vector<int>& info,
                      const std::vector<uint64_t>& keys) {
    const long n = static_cast<long>(keys.size());
    std::vector<Real4> packed(n);
    pack_elements(position, info, n, packed.data());
    write(pos_, packed.data(), n * sizeof(Real4), at * sizeof(Real4));
    write(keys_, keys.data(), n * sizeof(uint64_t), at * sizeof(uint64_t));
  }

  // Elements [0, n) of host arrays (3 reals, info) as the device's Real4 (x, y, z, packed info).
  static void pack_elements(const std::vector<double>& position, const std::vector<int>& info, long n, Real4* out) {
    for (long i = 0; i < n; ++i)
      out[i] = {static_cast<Real>(position[3 * i]), static_cast<Real>(position[3 * i + 1]),
                static_cast<Real>(position[3 * i + 2]), pack_info(info[i])};
  }
  static Real pack_info(int info) {
    Real w{};
    if constexpr (std::is_same_v<Real, float>) {
      std::memcpy(&w, &info, sizeof info);
    } else {
      const int64_t wide = info;
      std::memcpy(&w, &wide, sizeof wide);
    }
    return w;
  }
  std::vector<Real4> read_packed(const cl::Mem& m, long n, long at = 0) {
    std::vector<Real4> packed(n);
    read(m, packed.data(), n * sizeof(Real4), at * sizeof(Real4));
    return packed;
  }
  static void to_positions(const Real4* packed, long n, std::vector<double>& p) {  // keeps p's capacity
    p.resize(3 * n);
    for (long i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) p[3 * i + c] = packed[i][c];
  }
  static void to_positions(const std::vector<Real4>& packed, std::vector<double>& p) {
    to_positions(packed.data(), static_cast<long>(packed.size()), p);
  }
  static int unpack_info(Real w) {
    if constexpr (std::is_same_v<Real, float>) {
      int info;
      std::memcpy(&info, &w, sizeof info);
      return info;
    } else {
      int64_t wide;
      std::memcpy(&wide, &w, sizeof wide);
      return static_cast<int>(wide);
    }
  }
  static Real4 real4(const std::array<double, 3>& v) {
    return {static_cast<Real>(v[0]), static_cast<Real>(v[1]), static_cast<Real>(v[2]), 0};
  }
  static std::array<cl_int, 4> int4(const std::array<int, 3>& v) { return {v[0], v[1], v[2], 0}; }

  // Builds the program for pair term `pair_term` (-DSEMLB_PAIR_TERM=semlb_pair_NAME: the pair kernels' law) and
  // creates every kernel; a rebuild replaces them.
  void build(const std::string& pair_term);
  // Rebuilds the program when f.term is not the term it was built for (std::logic_error for an unregistered one),
  // then writes f's parameters into the pair kernels' table.
  void use_pair_term(const PairForces& f);

  // Kernel experiments (docs/engine.md): e.g. SEMLB_OPENCL_BUILD_OPTIONS=-DSEMLB_DOUBLE_RSQRT to time a variant.
  static std::string build_options() {
    const char* extra = std::getenv("SEMLB_OPENCL_BUILD_OPTIONS");
    return extra ? extra : "";
  }

  cl::Mem buffer(size_t bytes) {
    cl_int err = CL_SUCCESS;
    cl::Mem m(clCreateBuffer(ctx_.get(), CL_MEM_READ_WRITE, std::max<size_t>(bytes, 16), nullptr, &err));
    cl::check(err, "clCreateBuffer");
    return m;
  }
  void write(const cl::Mem& m, const void* data, size_t bytes, size_t offset = 0) {
    if (bytes)
      cl::check(clEnqueueWriteBuffer(queue_.get(), m.get(), CL_TRUE, offset, bytes, data, 0, nullptr, nullptr),
                "write buffer");
    moved(static_cast<long>(bytes), 0);
  }
  // bytes from `from` at `from_at` to `to` at `to_at`, on the device (nothing crosses to the host).
  void copy(const cl::Mem& from, const cl::Mem& to, size_t bytes, size_t from_at = 0, size_t to_at = 0) {
    if (bytes)
      cl::check(clEnqueueCopyBuffer(queue_.get(), from.get(), to.get(), from_at, to_at, bytes, 0, nullptr, nullptr),
                "copy buffer");
  }
  void read(const cl::Mem& m, void* data, size_t bytes, size_t offset = 0) {
    if (bytes)
      cl::check(clEnqueueReadBuffer(queue_.get(), m.get(), CL_TRUE, offset, bytes, data, 0, nullptr, nullptr),
                "read buffer");
    moved(0, static_cast<long>(bytes));
  }
  // Non-blocking read: `data` is filled once a later blocking call on the (in-order) queue returns.
  void read_async(const cl::Mem& m, void* data, size_t bytes, size_t offset = 0) {
    if (bytes)
      cl::check(clEnqueueReadBuffer(queue_.get(), m.get(), CL_FALSE, offset, bytes, data, 0, nullptr, nullptr),
                "read buffer");
    moved(0, static_cast<long>(bytes));
  }
  // Non-blocking write; `data` must stay unchanged until the returned event completes.
  cl::Event write_async(const cl::Mem& m, const void* data, size_t bytes, size_t offset = 0) {
    cl_event e = nullptr;
    if (bytes)
      cl::check(clEnqueueWriteBuffer(queue_.get(), m.get(), CL_FALSE, offset, bytes, data, 0, nullptr, &e),
                "write buffer");
    moved(static_cast<long>(bytes), 0);
    return cl::Event(e);
  }
  // `values` as T (Real for the force tables and element terms, double for the cell stage's rules) into m, written
  // only when they differ from what m last received this way: parameters rarely change.
  template <class T>
  void write_parameters(const cl::Mem& m, const std::vector<double>& values) {
    const std::vector<T> v(values.begin(), values.end());
    std::vector<unsigned char>& last = last_written_[m.get()];
    const auto* bytes = reinterpret_cast<const unsigned char*>(v.data());
    if (last.size() == v.size() * sizeof(T) && std::equal(last.begin(), last.end(), bytes)) return;
    write(m, v.data(), v.size() * sizeof(T));
    last.assign(bytes, bytes + v.size() * sizeof(T));
  }
  // The parameter buffer (kMaxPluginParams values of T) of plug-in `name` in `buffers`, holding `params`: what an
  // element term's or a removal rule's kernel reads.
  template <class T>
  cl_mem plugin_parameters(std::map<std::string, cl::Mem>& buffers, const std::string& name,
                           const std::vector<double>& params) {
    cl::Mem& m = buffers[name];
    if (!m) m = buffer(kMaxPluginParams * sizeof(T));
    write_parameters<T>(m, checked_plugin_params("plug-in", name, params));
    return m.get();
  }

  // Room for n elements (owned + ghosts); growing keeps elements [0, n_) and the owned elements' forces (the
  // local part, when the ghosts arrive between the two parts) by device copies.
  void reserve_elements(long n);
  // The most elements (owned and ghosts) one device holds: its kernels index them in 32 bits, failure codes as
  // 4 element + code. Beyond, InputError naming the count and the way out (more ranks).
  static void check_element_count(long n) {
    constexpr long kMax = (INT_MAX - 3) / 4;
    if (n > kMax)
      throw InputError(std::to_string(n) + " elements on one OpenCL device: more than " + std::to_string(kMax) +
                       ", the most its 32-bit element indices and failure codes reach; run on more ranks");
  }

  // The per-cell work arrays of the cell stage and the migration for n cells.
  void reserve_plan(long n);

  void allocate(long capacity);

  // starts[i] = counts[0] + ... + counts[i-1] for i <= n (three kernels); cursor[i] = starts[i]. With `gate`, the
  // kernels do nothing unless its first int is set (the neighbour list's builds).
  void exclusive_scan(const cl::Mem& counts, const cl::Mem& starts, const cl::Mem& sums, const cl::Mem& cursor, long n,
                      const cl::Mem* gate = nullptr) {
    const cl_int nb = static_cast<cl_int>(n), blocks = static_cast<cl_int>(round_up(n, kScanGroup) / kScanGroup);
    const cl_mem g = (gate ? *gate : always_).get();
    launch("scan_blocks", n, kScanGroup, g, counts.get(), starts.get(), sums.get(), nb,
           LocalBytes{kScanGroup * sizeof(cl_int)});
    launch("scan_sums", kScanGroup, kScanGroup, g, sums.get(), blocks, LocalBytes{kScanGroup * sizeof(cl_int)});
    launch("scan_add", n, kScanGroup, g, starts.get(), sums.get(), counts.get(), nb, cursor.get());
  }
  // `bytes` of m set to the int `value` (on the device).
  void fill(const cl::Mem& m, cl_int value, size_t bytes) {
    if (bytes)
      cl::check(clEnqueueFillBuffer(queue_.get(), m.get(), &value, sizeof value, 0, bytes, 0, nullptr, nullptr),
                "fill buffer");
  }
  // A non-blocking read whose completion the returned event tells.
  cl::Event read_event(const cl::Mem& m, void* data, size_t bytes) {
    cl_event e = nullptr;
    cl::check(clEnqueueReadBuffer(queue_.get(), m.get(), CL_FALSE, 0, bytes, data, 0, nullptr, &e), "read buffer");
    moved(0, static_cast<long>(bytes));
    return cl::Event(e);
  }
  size_t max_alloc() const {
    cl_ulong bytes = 0;
    clGetDeviceInfo(dev_.device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof bytes, &bytes, nullptr);
    return static_cast<size_t>(bytes);
  }

  // A counting sort by bin with its own buffers (the owned elements' and the ghosts'): per bin the count, the
  // first sorted slot (starts, bins + 1) and the scatter cursor; per sorted slot the position and element index.
  using BinSort = cl::BinSort;

  // Counting sort of elements [first, first + count) of pos_ by bin: count (atomics), exclusive scan, scatter
  // (bins.cl), growing s's buffers when the grid or the count outgrows them. The neighbour list's builds pass `gate`
  // (the kernels do nothing unless its first int is set), `ref` (a second copy of the sorted positions) and `items`
  // (work-items of the grid-stride kernels, at most count; 0: one per element).
  void sort_into_bins(const Grid& g, long first, long count, BinSort& s, const cl::Mem* gate = nullptr,
                      const cl::Mem* ref = nullptr, long items = 0);

  template <class T>
  void set_arg(cl_kernel k, cl_uint i, const T& v, const char* name) {
    if constexpr (std::is_same_v<T, LocalBytes>)
      cl::check(clSetKernelArg(k, i, v.bytes, nullptr), name);
    else
      cl::check(clSetKernelArg(k, i, sizeof(T), &v), name);
  }

  template <class T>
  static cl::KernelCapture::Arg captured(const T& v) {
    using Arg = cl::KernelCapture::Arg;
    if constexpr (std::is_same_v<T, LocalBytes>)
      return {Arg::kLocal, nullptr, {}, v.bytes};
    else if constexpr (std::is_same_v<T, cl_mem>)
      return {Arg::kBuffer, v, {}, 0};
    else {
      const auto* p = reinterpret_cast<const unsigned char*>(&v);
      return {Arg::kValue, nullptr, std::vector<unsigned char>(p, p + sizeof(T)), 0};
    }
  }

  template <class... Args>
  void launch(const char* name, long items, size_t group, const Args&... args) {
    const auto kernel = kernels_.find(name);
    if (kernel == kernels_.end())  // a call made by hand for a plug-in that is not registered
      throw std::logic_error(std::string("OpenCL kernel '") + name + "' is not in the program");
    if (items <= 0) return;
    count(name, items);  // every kernel enqueued, by name (launches(), launch_items())
    cl_kernel k = kernel->second.get();
    cl_uint i = 0;
    (set_arg(k, i++, args, name), ...);
    const size_t global = round_up(static_cast<size_t>(items), group);
    std::vector<cl::KernelCapture::Arg> capture;
    if (capture_.wants(name)) {
      (capture.push_back(captured(args)), ...);
      capture_.before(queue_.get(), program_.get(), global, group, capture);
    }
    cl_event raw = nullptr;
    const bool step_timer = timing();
    cl::check(clEnqueueNDRangeKernel(queue_.get(), k, 1, nullptr, &global, &group, 0, nullptr,
                                     profile_ || step_timer || measuring_ ? &raw : nullptr),
              name);
    if (!capture.empty()) capture_.after(queue_.get(), capture);
    if (!raw) return;
    cl::Event event(raw);
    if (measuring_) {
      measured_.push_back(std::move(event));  // pair_force_seconds reads them
      return;
    }
    if (!profile_) {
      pending_.emplace_back(step_key(name),
                            std::move(event));  // read at the next finish(): the host does not wait here
      return;
    }
    cl_event e = event.get();
    cl::check(clWaitForEvents(1, &e), "clWaitForEvents");
    const double t = seconds_of(e);
    kernel_seconds_[name] += t;
    if (step_timer) add_step_time(step_key(name), t);
  }
  // Kernels launched until the next call are timed under GROUP + name in step_kernel_seconds (Backend::device_parts:
  // "list:" for the neighbour list's builds); "" ends the group.
  void set_kernel_group(const char* group) { kernel_group_ = group; }

  // A step-timed kernel's key in step_kernel_seconds: "cells:" in the cell stage, then the kernel group, then the name.
  std::string step_key(const char* name) const {
    std::string key = phase() == "cells" ? "cells:" : "";
    key.append(kernel_group_).append(name);
    return key;
  }
  // Whether the work enqueued now is timed by the device timers (Backend::step_device_seconds).
  bool timing() const { return device_timing_ && is_step_phase(phase()); }
  // A completed event's device execution seconds (profiling END - START).
  static double seconds_of(cl_event e) {
    cl_ulong t0 = 0, t1 = 0;
    cl::check(clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_START, sizeof t0, &t0, nullptr), "profiling start");
    cl::check(clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_END, sizeof t1, &t1, nullptr), "profiling end");
    return t1 > t0 ? 1e-9 * static_cast<double>(t1 - t0) : 0.0;
  }
  void add_step_time(const std::string& name, double t) {
    step_device_s_ += t;
    step_kernel_s_[name] += t;
  }
  void settle_timers() override {
    if (pending_.empty()) return;
    std::vector<cl_event> events;
    for (const auto& p : pending_) events.push_back(p.second.get());
    cl::check(clWaitForEvents(static_cast<cl_uint>(events.size()), events.data()), "clWaitForEvents (device timers)");
    for (const auto& [name, event] : pending_) add_step_time(name, seconds_of(event.get()));
    pending_.clear();
  }

  // Per-cell arrays on the device (cell index order, as the host State): the cell stage reads one set and
  // writes the other, then swaps them. `fields` holds each cell's field record (cells.h): nf doubles per cell,
  // cell-major, the fields of the uploaded state (field_names_) in that order, whatever effects declared them.
  struct Cells {
    cl::Mem id, type, first, count, fields;
    long capacity = 0;
    int nf = 0;
    void allocate(OpenClBackend& b, long cap, int n_fields) {
      capacity = cap;
      nf = n_fields;
      id = b.buffer(cap * sizeof(uint64_t));
      for (cl::Mem* m : {&type, &first, &count}) *m = b.buffer(cap * sizeof(cl_int));
      fields = b.buffer(std::max(1L, cap * nf) * sizeof(double));  // a zero-size buffer is an OpenCL error
    }
    // Room for n cells of the current record (reallocated with slack, contents lost, when there is none).
    void reserve(OpenClBackend& b, long n) {
      if (n > capacity || nf != b.nf()) allocate(b, n + n / 4 + 64, b.nf());
    }
  };
  int nf() const { return static_cast<int>(field_names_.size()); }
  // `m` cells' records of `s`'s fields (0 for a field `s` lacks), cell-major, for a write into Cells::fields.
  std::vector<double> records_of(const State& s, long m) const;
  // Reads `m` records from `from` into the fields of `s` that the record holds (others stay as they are).
  void read_records(const cl::Mem& from, long m, State& s);

  void upload_cells(const State& s);
  // After a flags kernel (cells_owner, remove_NAME) set leave[c] in births_, owner[c] in divides_ and the element
  // counts in counts2_ of the n owned cells: the leavers go into leave_ (their elements into band_pos_), the others
  // are compacted in order (cells_split). Returns {leavers, their elements}; {0, 0} changes nothing.
  std::array<long, 2> split_cells(long n);

  template <class>
  friend class semlb::engine::NeighbourList;
  bool binned_, profile_ = false, has_fp64_ = false, cells_stale_ = false;
  bool device_timing_ = false;  // BackendConfig::device_timing
  std::string kernel_group_;    // set_kernel_group
  bool measuring_ = false;      // pair_force_seconds' launches: each one's event kept
  std::vector<cl::Event> measured_;
  cl::Mem scratch_force_, scratch_bound_, items_;  // pair_force_seconds' forces and bounds (discarded), slots
  long scratch_capacity_ = 0, items_capacity_ = 0;
  bool sorted_ = false;                                     // owned_sort_ holds the last local forces' sort
  Grid sort_grid_;                                          // its grid
  double last_cutoff_ = 0;                                  // and cutoff (um)
  std::vector<std::pair<std::string, cl::Event>> pending_;  // the device timers' events not yet read
  NeighbourList<Real> list_;                                // opencl-binned's local pairs when backend.skin > 0
  cl::Mem always_;                                          // an int 1: the gate of ungated scans
  Cells cell_, back_, leave_;             // leave_: the migration's leavers (leave_.first holds each one's new owner)
  std::vector<std::string> field_names_;  // the record's fields: the uploaded state's cell_fields, in name order
  long cells_ = 0, plan_capacity_ = 0, work_bins_capacity_ = 0, work_capacity_ = 0, bounds_capacity_ = 0;
  cl::Mem work_counts_, work_, owner_bounds_;  // W_s: elements per bin, per-slice sums; the interior boundaries
  std::vector<int> last_boundaries_;
  cl::Mem pos_back_, keys_back_, bounds_, cell_fail_, births_, old_centroid_, split_, counts2_, estarts_, esums_,
      divides_, dstarts_, dsums_;
  cl::DeviceInfo dev_{};
  cl::Context ctx_;
  cl::Queue queue_;
  cl::Program program_;
  std::string pair_term_;  // the pair term the program was built for
  std::string pair_exp_;   // the pair force law's exp: builtin | ranged | native (BackendConfig::pair_exp)
  std::string options_;    // the program's build options (program_options)
  cl::KernelCapture capture_;
  std::map<std::string, cl::Kernel> kernels_;
  std::map<cl_mem, std::vector<unsigned char>> last_written_;  // write_parameters' last bytes per buffer
  cl::Mem pos_, keys_, force_, fail_, table_;
  cl::Mem bound_;   // per owned element: the bound of its pair force sums (pair_force.h), checked by integrate
  long terms_ = 0;  // element terms added since zero_forces
  std::map<std::string, cl::Mem> term_params_, rule_params_;  // each element term's / removal rule's parameters
  BinSort owned_sort_, ghost_sort_;  // the local forces' bins; the ghosts' own (non-local forces)
  cl::Mem extent_, flags_, band_starts_, band_sums_, band_pos_;
  // The last bands() selection: both bands compacted (lower first) and near_[k] the owned element of slot k
  // (-1: listed in the lower band already), the non-local forces' items while near_valid_.
  cl::Mem band_out_pos_, band_out_keys_, near_;
  long band_capacity_ = 0, near_items_ = 0;
  bool near_valid_ = false;
  cl::Pinned down_, up_;                   // pinned host memory: the bands down, the ghosts up
  cl::Event up_done_;                      // the ghost upload's last write from up_
  long n_ = 0, owned_ = 0, capacity_ = 0;  // n_: owned + ghosts
};

}  // namespace semlb::engine::opencl_impl
