// The evaluator header compiled for the C++ backends, once per precision (Physics<float|double>), and the cell stage's
// rules on the host's arrays: the ground floor of the engine, which every other part includes and which includes none.
#pragma once
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#define SEMLB_LONG int64_t
#define SEMLB_ULONG uint64_t
#define SEMLB_CONST
#define SEMLB_EXP std::exp
#define SEMLB_SQRT std::sqrt
#define SEMLB_LOG std::log
#define SEMLB_COS std::cos
#define SEMLB_FMIN std::fmin
#define SEMLB_FMAX std::fmax

namespace semlb::engine::phys64 {
#define SEMLB_REAL double
#include "evaluator.h"
#undef SEMLB_REAL
using std::fma;
#define SEMLB_BITS(x) std::bit_cast<SEMLB_ULONG>(x)
#define SEMLB_FROM_BITS(b) std::bit_cast<double>(static_cast<SEMLB_ULONG>(b))
#include "exp.h"  // semlb_exp_ranged: the OpenCL double builds' `pair_exp: ranged`, here for its test
}  // namespace semlb::engine::phys64

namespace semlb::engine::phys32 {
#define SEMLB_REAL float
#include "evaluator.h"
#undef SEMLB_REAL
}  // namespace semlb::engine::phys32

// The cell stage's rules (cells.h) on the host State's arrays (3 doubles per element); see cells.cpp.
namespace semlb::engine::cellrules {
using phys64::semlb_info_pack;
using phys64::semlb_mix;
#define SEMLB_CELL_IN const double*
#define SEMLB_CELL_X(in, e, d) (in)[3 * (e) + (d)]
#define SEMLB_CELL_OUT double*
#define SEMLB_CELL_KEYS void*
#define SEMLB_CELL_PUT(out, keys, e, x, y, z, info, key) \
  ((out)[3 * (e)] = (x), (out)[3 * (e) + 1] = (y), (out)[3 * (e) + 2] = (z), (void)(keys), (void)(info), (void)(key))
#include "cells.h"
}  // namespace semlb::engine::cellrules

namespace semlb::engine {

template <class Real>
struct Physics;

#define SEMLB_PHYSICS(REAL, NS)                                                                               \
  template <>                                                                                                 \
  struct Physics<REAL> {                                                                                      \
    static int64_t fixed(REAL f) { return NS::semlb_to_fixed(f); }                                            \
    static REAL step(int64_t f, REAL dt_eta) { return NS::semlb_displacement(f, dt_eta); }                    \
    static REAL gauss(uint64_t s, uint64_t k, uint64_t t, uint64_t c) { return NS::semlb_gauss(s, k, t, c); } \
  };
SEMLB_PHYSICS(double, phys64)
SEMLB_PHYSICS(float, phys32)
#undef SEMLB_PHYSICS

// Counter-based random numbers for host-side effects (growth, tissue generator): the same generator.
inline double uniform01(uint64_t seed, uint64_t key, uint64_t step, uint64_t stream) {
  return phys64::semlb_uniform(seed, key, step, stream);
}
inline double gaussian(uint64_t seed, uint64_t key, uint64_t step, uint64_t stream) {
  return phys64::semlb_gauss(seed, key, step, stream);
}

}  // namespace semlb::engine
