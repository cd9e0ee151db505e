// OpenCL error checks, device listing and the platform/device choice.
#include "opencl.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/errors.hpp"
#include "common/text_io.hpp"

namespace semlb::engine::cl {

void check(cl_int status, const char* what) {
  if (status != CL_SUCCESS)
    throw std::runtime_error(std::string("OpenCL: ") + what + " failed (error " + std::to_string(status) + ")");
}

Pinned& Pinned::operator=(Pinned&& o) noexcept {
  if (this != &o) {
    reset();
    mem_ = std::move(o.mem_);
    queue_ = std::exchange(o.queue_, nullptr);
    ptr_ = std::exchange(o.ptr_, nullptr);
    bytes_ = std::exchange(o.bytes_, 0);
  }
  return *this;
}

void Pinned::reserve(cl_context ctx, cl_command_queue queue, size_t bytes) {
  if (bytes <= bytes_ && mem_) return;
  reset();
  const size_t want = std::max<size_t>(bytes + bytes / 4, 64);
  cl_int err = CL_SUCCESS;
  Mem m(clCreateBuffer(ctx, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR, want, nullptr, &err));
  check(err, "clCreateBuffer (pinned)");
  void* p = clEnqueueMapBuffer(queue, m.get(), CL_TRUE, CL_MAP_READ | CL_MAP_WRITE, 0, want, 0, nullptr, nullptr, &err);
  check(err, "clEnqueueMapBuffer (pinned)");
  mem_ = std::move(m);
  queue_ = queue;
  ptr_ = p;
  bytes_ = want;
}

void Pinned::reset() {
  if (mem_ && ptr_) {  // errors cannot be thrown from here; the buffer is released either way
    cl_event done = nullptr;
    if (clEnqueueUnmapMemObject(queue_, mem_.get(), ptr_, 0, nullptr, &done) == CL_SUCCESS && done) {
      clWaitForEvents(1, &done);
      clReleaseEvent(done);
    }
  }
  ptr_ = nullptr;
  bytes_ = 0;
  mem_ = Mem();
}

namespace {
// CL_PLATFORM_NAME / CL_DEVICE_NAME through clGetPlatformInfo / clGetDeviceInfo.
template <class Id, class Query>
std::string name_of(Id id, Query query, cl_uint param) {
  size_t n = 0;
  query(id, param, 0, nullptr, &n);
  std::string s(n, '\0');
  query(id, param, n, s.data(), nullptr);
  return s.c_str();
}
std::string info_string(cl_platform_id p) { return name_of(p, clGetPlatformInfo, CL_PLATFORM_NAME); }
std::string info_string(cl_device_id d) { return name_of(d, clGetDeviceInfo, CL_DEVICE_NAME); }
std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}
}  // namespace

std::vector<DeviceInfo> list_devices() {
  cl_uint np = 0;
  if (clGetPlatformIDs(0, nullptr, &np) != CL_SUCCESS || np == 0) return {};
  std::vector<cl_platform_id> platforms(np);
  check(clGetPlatformIDs(np, platforms.data(), nullptr), "clGetPlatformIDs");
  std::vector<DeviceInfo> out;
  for (auto p : platforms) {
    cl_uint nd = 0;
    if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &nd) != CL_SUCCESS) continue;
    std::vector<cl_device_id> devices(nd);
    check(clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, nd, devices.data(), nullptr), "clGetDeviceIDs");
    for (auto d : devices) {
      cl_device_type type = 0;
      clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof type, &type, nullptr);
      out.push_back({p, d, info_string(p), info_string(d), (type & CL_DEVICE_TYPE_GPU) != 0});
    }
  }
  return out;
}

DeviceInfo choose_device(const std::string& platform, int index, int local_rank) {
  const auto all = list_devices();
  if (all.empty()) throw InputError("backend: no OpenCL platform found (install an ICD, e.g. pocl-opencl-icd)");
  std::vector<std::string> names;
  for (const auto& d : all)
    if (std::find(names.begin(), names.end(), d.platform_name) == names.end()) names.push_back(d.platform_name);
  std::string chosen;
  if (!platform.empty()) {
    for (const auto& n : names)
      if (lower(n).find(lower(platform)) != std::string::npos) chosen = n;
  } else {
    std::vector<std::string> with_gpu;
    for (const auto& d : all)
      if (d.gpu && std::find(with_gpu.begin(), with_gpu.end(), d.platform_name) == with_gpu.end())
        with_gpu.push_back(d.platform_name);
    if (with_gpu.size() == 1)
      chosen = with_gpu[0];
    else if (names.size() == 1)
      chosen = names[0];
  }
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : "; ") + n;
  if (chosen.empty())
    throw DeviceChoiceError("platform", (platform.empty() ? std::string("several OpenCL platforms, choose one")
                                                          : "no platform matches '" + platform + "'") +
                                            " (found: " + known + ")");
  std::vector<DeviceInfo> devices;
  for (const auto& d : all)
    if (d.platform_name == chosen) devices.push_back(d);
  if (index < 0 || index >= static_cast<int>(devices.size()))
    throw DeviceChoiceError("device", "index " + std::to_string(index) + " but platform '" + chosen + "' has " +
                                          std::to_string(devices.size()) + " device(s)");
  const int chosen_index = static_cast<int>((index + local_rank) % devices.size());
  DeviceInfo d = devices[chosen_index];
  d.index = chosen_index;
  return d;
}

namespace {
std::vector<unsigned char> read_buffer(cl_command_queue q, cl_mem m) {
  size_t bytes = 0;
  check(clGetMemObjectInfo(m, CL_MEM_SIZE, sizeof bytes, &bytes, nullptr), "capture: buffer size");
  std::vector<unsigned char> out(bytes);
  check(clEnqueueReadBuffer(q, m, CL_TRUE, 0, bytes, out.data(), 0, nullptr, nullptr), "capture: read buffer");
  return out;
}
void write_file(const std::filesystem::path& p, const void* data, size_t bytes) {
  std::ofstream f(p, std::ios::binary);
  f.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  if (!f) throw std::runtime_error("SEMLB_OPENCL_CAPTURE: cannot write " + p.string());
}
}  // namespace

KernelCapture KernelCapture::from_env() {
  KernelCapture c;
  const char* v = std::getenv("SEMLB_OPENCL_CAPTURE");
  if (!v || !*v) return c;
  const std::string s = v;
  const size_t colon = s.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == s.size())
    throw InputError("SEMLB_OPENCL_CAPTURE: '" + s + "' is not KERNEL[@N]:DIR");
  c.kernel_ = s.substr(0, colon);
  c.dir_ = s.substr(colon + 1);
  if (const size_t at = c.kernel_.find('@'); at != std::string::npos) {  // KERNEL@N: the N-th launch
    c.launch_ = parse_integer(c.kernel_.substr(at + 1), "SEMLB_OPENCL_CAPTURE: launch ", 1);
    c.kernel_ = c.kernel_.substr(0, at);
  }
  if (c.kernel_.empty()) throw InputError("SEMLB_OPENCL_CAPTURE: '" + s + "' names no kernel");
  std::error_code ec;
  std::filesystem::create_directories(c.dir_, ec);
  if (ec || !std::filesystem::is_directory(c.dir_))
    throw InputError("SEMLB_OPENCL_CAPTURE: cannot create the folder '" + c.dir_ + "'" +
                     (ec ? ": " + ec.message() : ""));
  return c;
}

void KernelCapture::before(cl_command_queue q, cl_program program, size_t global, size_t group,
                           const std::vector<Arg>& args) const {
  const std::filesystem::path dir(dir_);
  std::filesystem::create_directories(dir);
  size_t size = 0;
  check(clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, nullptr), "capture: binary size");
  cl_uint devices = 0;
  check(clGetProgramInfo(program, CL_PROGRAM_NUM_DEVICES, sizeof devices, &devices, nullptr), "capture: devices");
  if (devices != 1) throw std::runtime_error("SEMLB_OPENCL_CAPTURE: the program is built for one device only");
  std::vector<unsigned char> binary(size);
  unsigned char* ptr = binary.data();
  check(clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof ptr, &ptr, nullptr), "capture: binary");
  write_file(dir / "program.bin", binary.data(), binary.size());
  std::ofstream launch(dir / "launch.txt");
  launch << "kernel " << kernel_ << "\nglobal " << global << "\ngroup " << group << "\n";
  for (size_t i = 0; i < args.size(); ++i) {
    const Arg& a = args[i];
    if (a.kind == Arg::kLocal) {
      launch << "arg " << i << " local " << a.local << "\n";
      continue;
    }
    const std::vector<unsigned char> bytes = a.kind == Arg::kBuffer ? read_buffer(q, a.mem) : a.bytes;
    write_file(dir / ("arg" + std::to_string(i) + ".bin"), bytes.data(), bytes.size());
    launch << "arg " << i << (a.kind == Arg::kBuffer ? " buffer " : " value ") << bytes.size() << "\n";
  }
  if (!launch.flush()) throw std::runtime_error("SEMLB_OPENCL_CAPTURE: cannot write " + (dir / "launch.txt").string());
}

void KernelCapture::after(cl_command_queue q, const std::vector<Arg>& args) {
  check(clFinish(q), "capture: clFinish");
  for (size_t i = 0; i < args.size(); ++i)
    if (args[i].kind == Arg::kBuffer) {
      const std::vector<unsigned char> bytes = read_buffer(q, args[i].mem);
      write_file(std::filesystem::path(dir_) / ("arg" + std::to_string(i) + ".after.bin"), bytes.data(), bytes.size());
    }
  done_ = true;
}

}  // namespace semlb::engine::cl
