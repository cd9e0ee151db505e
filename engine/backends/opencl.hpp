// RAII over the OpenCL C API and the explicit platform/device choice (never "index 0 by default").
#pragma once
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <string>
#include <utility>
#include <vector>

#include "common/errors.hpp"

namespace semlb::engine::cl {

void check(cl_int status, const char* what);  // throws std::runtime_error("OpenCL: WHAT failed (error N)")

template <class T, cl_int (*Release)(T)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(T h) : h_(h) {}
  Handle(Handle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      h_ = std::exchange(o.h_, nullptr);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  T get() const { return h_; }
  explicit operator bool() const { return h_ != nullptr; }

 private:
  void reset() {
    if (h_) Release(h_);
    h_ = nullptr;
  }
  T h_ = nullptr;
};

using Context = Handle<cl_context, clReleaseContext>;
using Queue = Handle<cl_command_queue, clReleaseCommandQueue>;
using Program = Handle<cl_program, clReleaseProgram>;
using Kernel = Handle<cl_kernel, clReleaseKernel>;
using Mem = Handle<cl_mem, clReleaseMemObject>;
using Event = Handle<cl_event, clReleaseEvent>;

// Pinned host memory (a CL_MEM_ALLOC_HOST_PTR buffer mapped once for its lifetime): reads and writes between a
// device buffer and data() run at full DMA speed and may be non-blocking. Unmapped (and released) on
// destruction; `queue` must outlive it. Grows by reallocation (the contents go).
class Pinned {
 public:
  Pinned() = default;
  Pinned(Pinned&& o) noexcept { *this = std::move(o); }
  Pinned& operator=(Pinned&& o) noexcept;
  Pinned(const Pinned&) = delete;
  Pinned& operator=(const Pinned&) = delete;
  ~Pinned() { reset(); }
  // Room for at least `bytes` (allocates 1.25x when it grows); throws on an OpenCL error.
  void reserve(cl_context ctx, cl_command_queue queue, size_t bytes);
  char* data() const { return static_cast<char*>(ptr_); }
  size_t size() const { return bytes_; }

 private:
  void reset();
  Mem mem_;
  cl_command_queue queue_ = nullptr;
  void* ptr_ = nullptr;
  size_t bytes_ = 0;
};

struct DeviceInfo {
  cl_platform_id platform;
  cl_device_id device;
  std::string platform_name, device_name;
  bool gpu;
  int index = 0;  // within its platform (choose_device sets it)
};

// Every platform with its devices, as "platform: device" lines (for errors and `semlb sim --list-devices`).
std::vector<DeviceInfo> list_devices();
// The platform whose name contains `platform` (case-insensitive); empty: the only platform with a GPU,
// else the only platform. `index` counts devices within that platform; `local_rank` (the rank among the
// processes of this host) adds to it, wrapping around, so ranks spread over the devices or share them.
// Throws DeviceChoiceError when none matches.
DeviceInfo choose_device(const std::string& platform, int index, int local_rank = 0);
// choose_device's refusal: the setting at fault (`key`: "platform" or "device") and why; what() is "backend.KEY: WHY"
// for callers without the scene (the backend names where the key was given: Settings::fail).
struct DeviceChoiceError : InputError {
  DeviceChoiceError(const std::string& key, const std::string& why)
      : InputError("backend." + key + ": " + why), key(key), why(why) {}
  std::string key, why;
};

// One launch of a named kernel written to a folder, so that tools which cannot profile OpenCL (Nsight
// Compute) can replay it through the CUDA driver (scripts/gpu/ncu_replay.cpp; docs/performance.md "Profiling
// the force kernel"). Switched on by `SEMLB_OPENCL_CAPTURE=KERNEL[@N]:DIR`; the N-th launch of KERNEL (default 1;
// a later one shows the steady state: the neighbour list's first launch runs before kmax has grown) writes
//   DIR/program.bin   the program binary (PTX text on NVIDIA's platform),
//   DIR/launch.txt    "kernel NAME", "global N", "group N", then per argument "arg I buffer BYTES", "arg I value
//                     BYTES" or "arg I local BYTES",
//   DIR/argI.bin      each buffer before the launch (a value: its bytes), DIR/argI.after.bin each buffer after it.
// Other launches are not captured. Errors (InputError naming the variable): a malformed value, a DIR that cannot be
// created; the backend refuses a KERNEL it does not have.
class KernelCapture {
 public:
  struct Arg {
    enum Kind { kBuffer, kValue, kLocal } kind;
    cl_mem mem = nullptr;              // kBuffer
    std::vector<unsigned char> bytes;  // kValue
    size_t local = 0;                  // kLocal: bytes of local memory
  };
  // SEMLB_OPENCL_CAPTURE, or a capture that wants nothing; creates DIR (InputError naming the variable if it
  // cannot).
  static KernelCapture from_env();
  const std::string& kernel() const { return kernel_; }  // empty: capturing nothing
  // Counts the launches of `kernel`; true for the one to capture.
  bool wants(const std::string& kernel) {
    return !done_ && !kernel_.empty() && kernel == kernel_ && ++seen_ == launch_;
  }
  // Before the launch is enqueued (reads the buffers: blocking) and after it (waits for the queue).
  void before(cl_command_queue q, cl_program program, size_t global, size_t group, const std::vector<Arg>& args) const;
  void after(cl_command_queue q, const std::vector<Arg>& args);

 private:
  std::string kernel_, dir_;
  long launch_ = 1, seen_ = 0;
  bool done_ = false;
};

// The device buffers of one counting sort by bin (OpenClBackend::sort_into_bins): per-bin counts, starts (bins + 1),
// scatter cursor and scan block sums; per element its bin, its sorted position and its element index. Capacities:
// `bins` bins, `elements` elements.
struct BinSort {
  Mem counts, starts, cursor, sums, bin, sorted_pos, sorted_index;
  long bins = 0, elements = 0;
};

}  // namespace semlb::engine::cl
