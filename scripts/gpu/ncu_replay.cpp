// Replays one captured OpenCL kernel launch (SEMLB_OPENCL_CAPTURE, engine/backends/opencl.hpp) through the CUDA
// driver API, so that Nsight Compute, which cannot profile OpenCL, can profile the same PTX on the same data.
//
// Usage: ncu_replay DIR [REPEATS]
//   DIR      a capture folder (program.bin = the PTX that NVIDIA's OpenCL compiler produced, launch.txt, argI.bin)
//   REPEATS  timed launches after one checked launch (default 20; 1 under ncu)
// It loads that kernel's entry alone (the program's other kernels take __local arguments, which the CUDA driver
// refuses) with textual changes that CUDA needs and prints each: loads through __constant
// pointer arguments become global non-coherent loads (CUDA cannot bind an argument into a constant bank), and
// the OpenCL global offset (%envreg, set by the OpenCL runtime) becomes 0, and the target loses OpenCL's
// texmode_independent (the CUDA driver refuses such a module: CUDA_ERROR_INVALID_IMAGE). Then it checks that one launch
// reproduces every buffer the OpenCL launch wrote, bit for bit (argI.after.bin), and prints the kernel's
// device time (cuEvent) per launch, each launch starting from the captured inputs.
// Exit code 0: replay identical; 1: any difference or CUDA error; 2: bad usage or capture folder.
// Build (on a machine with the CUDA toolkit): g++ -O2 -std=c++17 ncu_replay.cpp -I/usr/local/cuda/include -lcuda
#include <cuda.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

void check(CUresult r, const char* what) {
  if (r == CUDA_SUCCESS) return;
  const char* msg = nullptr;
  cuGetErrorString(r, &msg);
  std::fprintf(stderr, "ncu_replay: %s failed: %s\n", what, msg ? msg : "?");
  std::exit(1);
}

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr, "ncu_replay: %s\nusage: ncu_replay DIR [REPEATS]\n", why.c_str());
  std::exit(2);
}

std::vector<unsigned char> slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) usage("cannot read " + path);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

struct Arg {
  std::string kind;  // buffer, value, local
  size_t bytes = 0;
  std::vector<unsigned char> before, after;
  CUdeviceptr dev = 0;
};

// The module header (version, target, module-scope .const/.global data) and the one entry `kernel`: the other
// kernels of the OpenCL program take __local (.ptr .shared) arguments, which the CUDA driver refuses to load.
std::string only_entry(const std::string& ptx, const std::string& kernel) {
  const size_t first = ptx.find("\n.entry");
  const size_t begin = ptx.find("\n.entry " + kernel + "(");
  if (first == std::string::npos || begin == std::string::npos) usage("program.bin: no PTX entry " + kernel);
  const size_t end = ptx.find("\n}\n", begin);
  if (end == std::string::npos) usage("program.bin: the entry " + kernel + " does not end");
  const std::string body = ptx.substr(begin, end + 3 - begin);
  if (body.find("call") != std::string::npos)
    usage("program.bin: the entry " + kernel + " calls functions (not replayed)");
  return ptx.substr(0, first) + body;
}

// The PTX changes described above; prints what it changed.
std::string patch(std::string ptx) {
  std::smatch m;
  const std::regex const_param(R"(\.ptr\s+\.const)");
  const std::regex const_load(R"(ld\.const((?:\.[a-z0-9]+)+)(\s+(?:\{[^}]*\}|[^,\s]+),\s*\[%rd))");
  const std::regex cvta_const(R"(cvta\.const\.u64)");
  const std::regex envreg(R"(%envreg[0-9]+)");
  const auto count = [](const std::string& s, const std::regex& r) {
    return std::distance(std::sregex_iterator(s.begin(), s.end(), r), std::sregex_iterator());
  };
  std::printf(
      "patch: %ld __constant pointer parameter(s), %ld register-addressed constant load(s), %ld cvta.const, "
      "%ld %%envreg read(s)\n",
      static_cast<long>(count(ptx, const_param)), static_cast<long>(count(ptx, const_load)),
      static_cast<long>(count(ptx, cvta_const)), static_cast<long>(count(ptx, envreg)));
  std::istringstream lines(ptx);
  for (std::string line; std::getline(lines, line);)
    if (line.find("%envreg") != std::string::npos) std::printf("  envreg line: %s\n", line.c_str());
  ptx = std::regex_replace(ptx, const_param, ".ptr .global");
  ptx = std::regex_replace(ptx, const_load, "ld.global.nc$1$2");
  ptx = std::regex_replace(ptx, cvta_const, "cvta.global.u64");
  ptx = std::regex_replace(ptx, envreg, "0");
  ptx = std::regex_replace(ptx, std::regex(R"(,\s*texmode_independent)"),
                           "");  // OpenCL's texture mode; CUDA's is unified
  return ptx;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) usage("expected a capture folder");
  const std::string dir = argv[1];
  int repeats = 20;
  if (argc == 3) {
    char* end = nullptr;
    const long r = std::strtol(argv[2], &end, 10);
    if (*end || r < 1 || r > 100000) usage(std::string("REPEATS: '") + argv[2] + "' is not an integer in 1..100000");
    repeats = static_cast<int>(r);
  }
  std::ifstream launch(dir + "/launch.txt");
  if (!launch) usage("cannot read " + dir + "/launch.txt");
  std::string kernel;
  size_t global = 0, group = 0;
  std::vector<Arg> args;
  int lineno = 0;
  for (std::string line; std::getline(launch, line);) {
    ++lineno;
    std::istringstream in(line);
    std::string key;
    in >> key;
    bool ok = true;
    if (key == "kernel")
      ok = static_cast<bool>(in >> kernel);
    else if (key == "global")
      ok = static_cast<bool>(in >> global);
    else if (key == "group")
      ok = static_cast<bool>(in >> group);
    else if (key == "arg") {
      size_t index = 0;
      Arg a;
      ok = (in >> index >> a.kind >> a.bytes) && index == args.size();
      args.push_back(a);
    } else
      ok = false;
    if (!ok) usage(dir + "/launch.txt:" + std::to_string(lineno) + ": cannot read '" + line + "'");
  }
  if (kernel.empty() || !global || !group || global % group)
    usage(dir + "/launch.txt: kernel, global and group needed");
  for (size_t i = 0; i < args.size(); ++i) {
    Arg& a = args[i];
    if (a.kind == "local") usage("argument " + std::to_string(i) + ": __local arguments are not replayed");
    a.before = slurp(dir + "/arg" + std::to_string(i) + ".bin");
    if (a.before.size() != a.bytes) usage("arg" + std::to_string(i) + ".bin: size differs from launch.txt");
    if (a.kind == "buffer") a.after = slurp(dir + "/arg" + std::to_string(i) + ".after.bin");
  }
  std::vector<unsigned char> ptx = slurp(dir + "/program.bin");
  const std::string text = patch(only_entry(std::string(ptx.begin(), std::find(ptx.begin(), ptx.end(), '\0')), kernel));
  std::ofstream(dir + "/patched.ptx") << text;  // for ptxas -v and for reading
  // A cubin that ptxas made of patched.ptx, when present, is loaded instead (scripts/gpu/ncu_forces.sh's fallback).
  std::vector<unsigned char> cubin;
  if (std::ifstream(dir + "/patched.cubin")) {
    cubin = slurp(dir + "/patched.cubin");
    std::printf("loading %s/patched.cubin instead of the PTX\n", dir.c_str());
  }

  check(cuInit(0), "cuInit");
  CUdevice device;
  check(cuDeviceGet(&device, 0), "cuDeviceGet");
  CUcontext ctx;
  check(cuDevicePrimaryCtxRetain(&ctx, device), "cuDevicePrimaryCtxRetain");
  check(cuCtxSetCurrent(ctx), "cuCtxSetCurrent");
  CUmodule module;
  char log[8192] = {0}, info[8192] = {0};
  CUjit_option opts[] = {CU_JIT_ERROR_LOG_BUFFER, CU_JIT_ERROR_LOG_BUFFER_SIZE_BYTES, CU_JIT_INFO_LOG_BUFFER,
                         CU_JIT_INFO_LOG_BUFFER_SIZE_BYTES};
  void* vals[] = {log, reinterpret_cast<void*>(sizeof log), info, reinterpret_cast<void*>(sizeof info)};
  if (const CUresult r = cuModuleLoadDataEx(
          &module, cubin.empty() ? static_cast<const void*>(text.c_str()) : cubin.data(), 4, opts, vals);
      r != CUDA_SUCCESS) {
    const char* name = nullptr;
    cuGetErrorName(r, &name);
    std::fprintf(stderr, "ncu_replay: the PTX (%s/patched.ptx) did not load: %s\n%s\n%s\n", dir.c_str(),
                 name ? name : "?", log, info);
    return 1;
  }
  CUfunction fn;
  check(cuModuleGetFunction(&fn, module, kernel.c_str()), "cuModuleGetFunction");
  int regs = 0, local = 0;
  cuFuncGetAttribute(&regs, CU_FUNC_ATTRIBUTE_NUM_REGS, fn);
  cuFuncGetAttribute(&local, CU_FUNC_ATTRIBUTE_LOCAL_SIZE_BYTES, fn);
  std::printf("kernel %s: global %zu, group %zu, %d registers, %d bytes of local (spill) memory per thread\n",
              kernel.c_str(), global, group, regs, local);

  std::vector<void*> params;
  for (Arg& a : args) {
    if (a.kind == "buffer") {
      check(cuMemAlloc(&a.dev, a.bytes), "cuMemAlloc");
      params.push_back(&a.dev);
    } else {
      params.push_back(a.before.data());
    }
  }
  const auto restore = [&] {
    for (Arg& a : args)
      if (a.kind == "buffer") check(cuMemcpyHtoD(a.dev, a.before.data(), a.bytes), "cuMemcpyHtoD");
  };
  const auto run = [&] {
    check(cuLaunchKernel(fn, static_cast<unsigned>(global / group), 1, 1, static_cast<unsigned>(group), 1, 1, 0,
                         nullptr, params.data(), nullptr),
          "cuLaunchKernel");
  };
  restore();
  run();
  check(cuCtxSynchronize(), "the checked launch");
  bool identical = true;
  for (size_t i = 0; i < args.size(); ++i) {
    Arg& a = args[i];
    if (a.kind != "buffer") continue;
    std::vector<unsigned char> out(a.bytes);
    check(cuMemcpyDtoH(out.data(), a.dev, a.bytes), "cuMemcpyDtoH");
    size_t differ = 0;
    for (size_t k = 0; k < a.bytes; ++k) differ += out[k] != a.after[k];
    if (differ) {
      identical = false;
      std::printf("arg %zu: %zu of %zu bytes differ from the OpenCL launch\n", i, differ, a.bytes);
    }
  }
  std::printf("replay %s the OpenCL launch's buffers bit for bit\n", identical ? "reproduces" : "DOES NOT reproduce");

  CUevent t0, t1;
  check(cuEventCreate(&t0, CU_EVENT_DEFAULT), "cuEventCreate");
  check(cuEventCreate(&t1, CU_EVENT_DEFAULT), "cuEventCreate");
  std::vector<float> ms;
  for (int r = 0; r < repeats; ++r) {
    restore();
    check(cuEventRecord(t0, nullptr), "cuEventRecord");
    run();
    check(cuEventRecord(t1, nullptr), "cuEventRecord");
    check(cuEventSynchronize(t1), "cuEventSynchronize");
    float t = 0;
    check(cuEventElapsedTime(&t, t0, t1), "cuEventElapsedTime");
    ms.push_back(t);
  }
  std::sort(ms.begin(), ms.end());
  double sum = 0;
  for (float t : ms) sum += t;
  std::printf("device time over %d launches: min %.3f ms, median %.3f ms, mean %.3f ms, max %.3f ms\n", repeats,
              ms.front(), ms[ms.size() / 2], sum / ms.size(), ms.back());
  for (Arg& a : args)
    if (a.dev) cuMemFree(a.dev);
  cuModuleUnload(module);
  cuDevicePrimaryCtxRelease(device);
  return identical ? 0 : 1;
}
