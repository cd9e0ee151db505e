// The OpenCL program as an OpenCL backend builds it (the embedded kernels.cl with its parts and that backend's build
// options), plus test kernels, on the backend's device: for tests that look into the kernels (an exp the options
// select, a variant's work-group size).
#pragma once
#include <memory>
#include <stdexcept>
#include <string>

#include "engine/backends/opencl_backend.hpp"

namespace semlb::engine {
extern const char* const kKernelSource;  // kernels.cl with its parts (engine/CMakeLists.txt)

namespace testing {

// Builds the program for an OpenCL double backend made from `c` (make_backend: its settings checked) with `extra`
// source appended; std::runtime_error with the build log when it does not build. `options` is what the backend used.
class KernelProgram {
 public:
  KernelProgram(const BackendConfig& c, const std::string& extra) {
    const std::unique_ptr<Backend> made = make_backend(c);
    const auto* backend = dynamic_cast<const opencl_impl::OpenClBackend<double>*>(made.get());
    if (!backend) throw std::logic_error("KernelProgram: not an OpenCL double backend");
    options = backend->program_options();
    device = cl::choose_device(c.platform, c.device);
    cl_int err = CL_SUCCESS;
    ctx = cl::Context(clCreateContext(nullptr, 1, &device.device, nullptr, nullptr, &err));
    cl::check(err, "clCreateContext");
    queue = cl::Queue(clCreateCommandQueue(ctx.get(), device.device, 0, &err));
    cl::check(err, "clCreateCommandQueue");
    const std::string source = std::string(kKernelSource) + "\n" + extra;
    const char* text = source.c_str();
    program = cl::Program(clCreateProgramWithSource(ctx.get(), 1, &text, nullptr, &err));
    cl::check(err, "clCreateProgramWithSource");
    if (clBuildProgram(program.get(), 1, &device.device, options.c_str(), nullptr, nullptr) != CL_SUCCESS) {
      size_t n = 0;
      clGetProgramBuildInfo(program.get(), device.device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
      std::string log(n, '\0');
      clGetProgramBuildInfo(program.get(), device.device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
      throw std::runtime_error("KernelProgram: the program did not build:\n" + log);
    }
  }
  cl::Kernel kernel(const char* name) const {
    cl_int err = CL_SUCCESS;
    cl::Kernel k(clCreateKernel(program.get(), name, &err));
    cl::check(err, "clCreateKernel");
    return k;
  }

  std::string options;
  cl::DeviceInfo device{};
  cl::Context ctx;
  cl::Queue queue;
  cl::Program program;
};

}  // namespace testing
}  // namespace semlb::engine
