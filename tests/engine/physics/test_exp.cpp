// physics/exp.h: semlb_exp_ranged against the host's libm exp (its 1-ulp contract, its edges), and backend.pair_exp in
// the kernels: each value the exp it names, ranged with the host's bits.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "../kernel_program.hpp"
#include "engine/physics/cpu_physics.hpp"

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

// Each value of backend.pair_exp reaches the kernels as the exp it names: the OpenCL program built with the options an
// opencl-binned double backend used (its config through kernels.cl's macros) evaluates SEMLB_PAIR_EXP, the pair laws'
// exp, beside the built-in exp and float's native exp. ranged gives the host's semlb_exp_ranged bit for bit, so the
// 1-ulp bound measured above holds on the device (a ranged run's positions are mostly the builtin's, which says
// nothing); builtin and native give theirs.
TEST(Exp, EachPairExpReachesTheKernelsAndRangedGivesTheHostsBits) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  std::vector<double> x = arguments();
  x.resize(100000);
  x.insert(x.end(), {0.0, -708.39, -708.5, -kInf, std::nan("")});
  const size_t n = x.size();
  for (const std::string exp : {"builtin", "ranged", "native"}) {
    BackendConfig c;
    c.name = "opencl-binned";
    c.pair_exp = exp;
    std::unique_ptr<testing::KernelProgram> built;
    try {
      built = std::make_unique<testing::KernelProgram>(
          c,
          "__kernel void probe(__global const double* x, __global double* y, int which) {\n"
          "  const double v = x[get_global_id(0)];\n"
          "  y[get_global_id(0)] = which == 0 ? SEMLB_PAIR_EXP(v) : which == 1 ? exp(v)\n"
          "                      : (double)native_exp((float)v);\n}\n");
    } catch (const InputError& e) {  // a device without double precision
      GTEST_SKIP() << e.what();
    }
    const testing::KernelProgram& p = *built;
    EXPECT_NE(p.options.find("-DSEMLB_PAIR_EXP_"), std::string::npos);
    const cl::Kernel kernel = p.kernel("probe");
    cl_int err = CL_SUCCESS;
    const size_t bytes = n * sizeof(double);
    cl::Mem in(clCreateBuffer(p.ctx.get(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, x.data(), &err));
    cl::check(err, "clCreateBuffer");
    cl::Mem out(clCreateBuffer(p.ctx.get(), CL_MEM_WRITE_ONLY, bytes, nullptr, &err));
    cl::check(err, "clCreateBuffer");
    // which: 0 the pair laws' exp, 1 the built-in exp, 2 float's native exp
    const auto eval = [&](cl_int which) {
      cl_mem a = in.get(), b = out.get();
      cl::check(clSetKernelArg(kernel.get(), 0, sizeof a, &a), "clSetKernelArg");
      cl::check(clSetKernelArg(kernel.get(), 1, sizeof b, &b), "clSetKernelArg");
      cl::check(clSetKernelArg(kernel.get(), 2, sizeof which, &which), "clSetKernelArg");
      cl::check(clEnqueueNDRangeKernel(p.queue.get(), kernel.get(), 1, nullptr, &n, nullptr, 0, nullptr, nullptr),
                "clEnqueueNDRangeKernel");
      std::vector<double> y(n);
      cl::check(clEnqueueReadBuffer(p.queue.get(), out.get(), CL_TRUE, 0, bytes, y.data(), 0, nullptr, nullptr),
                "clEnqueueReadBuffer");
      return y;
    };
    // how many of the values differ from `want`, bit for bit (NaN equal to NaN)
    const auto differ = [&](const std::vector<double>& got, const std::vector<double>& want) {
      long d = 0;
      for (size_t i = 0; i < n; ++i)
        d += std::bit_cast<uint64_t>(got[i]) != std::bit_cast<uint64_t>(want[i]) &&
             !(std::isnan(got[i]) && std::isnan(want[i]));
      return d;
    };
    const auto pair = eval(0), builtin = eval(1), native = eval(2);
    ASSERT_GT(differ(builtin, native), 1000) << "the probe cannot tell the builtin from native";
    if (exp == "ranged") {
      std::vector<double> host(n);
      for (size_t i = 0; i < n; ++i) host[i] = semlb_exp_ranged(x[i]);
      EXPECT_EQ(differ(pair, host), 0) << "of " << n << " on " << p.device.device_name;
      EXPECT_TRUE(std::isnan(pair[n - 1]));
    } else {
      EXPECT_EQ(differ(pair, exp == "builtin" ? builtin : native), 0) << exp;
    }
  }
}

}  // namespace
}  // namespace semlb::engine
