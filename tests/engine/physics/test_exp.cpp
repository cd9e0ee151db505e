// physics/exp.h: semlb_exp_ranged against libm's exp (its 1-ulp contract, its edges), and the same bits from an
// OpenCL double device as from the host, so the bound measured here holds in the kernels.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "common/text_io.hpp"
#include "engine/backends/opencl.hpp"
#include "engine/physics/cpu_physics.hpp"
#include "../../run_command.hpp"

namespace semlb::engine {
namespace {

using phys64::semlb_exp_ranged;
constexpr double kInf = std::numeric_limits<double>::infinity();

// The distance in doubles (ulps) between two finite positive doubles.
uint64_t ulps(double a, double b) {
  const uint64_t x = std::bit_cast<uint64_t>(a), y = std::bit_cast<uint64_t>(b);
  return x > y ? x - y : y - x;
}

// The arguments the contract covers: uniform over [-708.39, 709], uniform over the pair laws' usual [-40, 0], and the
// two doubles either side of each rounding boundary of k, (k + 1/2) ln2, for k from -1021 to 1022.
std::vector<double> arguments() {
  std::mt19937_64 g(20261205);
  std::uniform_real_distribution<double> wide(-708.39, 709), usual(-40, 0);
  std::vector<double> x;
  for (int i = 0; i < 1000000; ++i) x.push_back(i % 2 ? wide(g) : usual(g));
  for (int k = -1021; k <= 1022; ++k) {
    const double b = (k + 0.5) * M_LN2;
    x.insert(x.end(), {std::nextafter(b, -1e9), b, std::nextafter(b, 1e9)});
  }
  return x;
}

TEST(Exp, RangedIsWithinOneUlpOfLibmOverItsRange) {
  uint64_t worst = 0;
  double at = 0;
  long off = 0;
  const auto xs = arguments();
  for (double x : xs) {
    const uint64_t d = ulps(semlb_exp_ranged(x), std::exp(x));
    if (d > worst) worst = d, at = x;
    off += d > 0;
  }
  EXPECT_LE(worst, 1u) << "at x = " << at;
  // most results are libm's own: a wrong coefficient or a lost ln2 part would move most of them
  EXPECT_LT(static_cast<double>(off), 0.2 * static_cast<double>(xs.size()));
}

TEST(Exp, RangedEdges) {
  EXPECT_EQ(semlb_exp_ranged(0.0), 1.0);
  EXPECT_EQ(semlb_exp_ranged(-0.0), 1.0);
  EXPECT_LE(ulps(semlb_exp_ranged(-708.39), std::exp(-708.39)), 1u);  // 2.24e-308, just above the smallest normal
  EXPECT_LE(ulps(semlb_exp_ranged(709.0), std::exp(709.0)), 1u);
  // below -708.39: 0 where libm gives the smallest normals, subnormals or 0 (below 2.24e-308)
  for (double x : {std::nextafter(-708.39, -1e9), -708.5, -745.0, -1e6, -1e300, -kInf}) {
    EXPECT_EQ(semlb_exp_ranged(x), 0.0) << x;
    EXPECT_LT(std::exp(x), 2.24e-308) << x;
  }
  EXPECT_TRUE(std::isnan(semlb_exp_ranged(std::nan(""))));  // a NaN distance reaches the clamp as NaN, as with libm
}

TEST(Exp, OpenClDoubleGivesTheHostsBits) {
  cl::DeviceInfo dev;
  try {
    dev = cl::choose_device("", 0);
  } catch (const std::exception& e) {
    GTEST_SKIP() << "no OpenCL device: " << e.what();
  }
  cl_device_fp_config fp64 = 0;
  clGetDeviceInfo(dev.device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64, &fp64, nullptr);
  if (!fp64) GTEST_SKIP() << dev.device_name << " has no double precision";
  // exp.h under kernels.cl's own definitions (backends/kernels.cl: FP_CONTRACT OFF, as_ulong / as_double)
  const std::string source =
      "#pragma OPENCL FP_CONTRACT OFF\n#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n"
      "#define SEMLB_BITS as_ulong\n#define SEMLB_FROM_BITS as_double\n" +
      read_file(test::source("engine/physics/exp.h")) +
      "\n__kernel void f(__global const double* x, __global double* y) {\n"
      "  y[get_global_id(0)] = semlb_exp_ranged(x[get_global_id(0)]);\n}\n";
  cl_int err = CL_SUCCESS;
  cl::Context ctx(clCreateContext(nullptr, 1, &dev.device, nullptr, nullptr, &err));
  cl::check(err, "clCreateContext");
  cl::Queue queue(clCreateCommandQueue(ctx.get(), dev.device, 0, &err));
  cl::check(err, "clCreateCommandQueue");
  const char* text = source.c_str();
  cl::Program program(clCreateProgramWithSource(ctx.get(), 1, &text, nullptr, &err));
  cl::check(err, "clCreateProgramWithSource");
  ASSERT_EQ(clBuildProgram(program.get(), 1, &dev.device, "", nullptr, nullptr), CL_SUCCESS);
  cl::Kernel kernel(clCreateKernel(program.get(), "f", &err));
  cl::check(err, "clCreateKernel");

  std::vector<double> x = arguments();
  x.resize(200000);
  x.insert(x.end(), {0.0, -708.39, -708.5, -kInf, std::nan("")});
  const size_t n = x.size(), bytes = n * sizeof(double);
  cl::Mem in(clCreateBuffer(ctx.get(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, x.data(), &err));
  cl::check(err, "clCreateBuffer");
  cl::Mem out(clCreateBuffer(ctx.get(), CL_MEM_WRITE_ONLY, bytes, nullptr, &err));
  cl::check(err, "clCreateBuffer");
  cl_mem a = in.get(), b = out.get();
  cl::check(clSetKernelArg(kernel.get(), 0, sizeof a, &a), "clSetKernelArg");
  cl::check(clSetKernelArg(kernel.get(), 1, sizeof b, &b), "clSetKernelArg");
  cl::check(clEnqueueNDRangeKernel(queue.get(), kernel.get(), 1, nullptr, &n, nullptr, 0, nullptr, nullptr),
            "clEnqueueNDRangeKernel");
  std::vector<double> y(n);
  cl::check(clEnqueueReadBuffer(queue.get(), out.get(), CL_TRUE, 0, bytes, y.data(), 0, nullptr, nullptr),
            "clEnqueueReadBuffer");
  long differ = 0;
  for (size_t i = 0; i < n; ++i)
    differ += std::bit_cast<uint64_t>(y[i]) != std::bit_cast<uint64_t>(semlb_exp_ranged(x[i])) &&
              !(std::isnan(y[i]) && std::isnan(x[i]));
  EXPECT_EQ(differ, 0) << "of " << n << " on " << dev.device_name;
  EXPECT_TRUE(std::isnan(y[n - 1]));
}

}  // namespace
}  // namespace semlb::engine
