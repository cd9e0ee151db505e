// The pair term of SEMLB_PAIR_HEADER (a string literal) and SEMLB_PAIR_NAME (its name, an identifier) compiled for the
// C++ backends in both precisions, with the pair loop's body (pairs/pair_force.h) over its law: namespaces
// phys64::NAME (double) and phys32::NAME (float) of cpu_physics.hpp, each with `pair`, a PairEvaluator. A term's
// NAME.cpp includes this file once. No include guard: one inclusion per term file.
#include "physics/cpu_physics.hpp"

#if !defined(SEMLB_PAIR_HEADER) || !defined(SEMLB_PAIR_NAME)
#error "define SEMLB_PAIR_HEADER and SEMLB_PAIR_NAME before including pairs/instantiate.hpp"
#endif
#define SEMLB_PAIR_CAT2(a, b) a##b
#define SEMLB_PAIR_CAT(a, b) SEMLB_PAIR_CAT2(a, b)
#define SEMLB_PAIR_LAW SEMLB_PAIR_CAT(semlb_pair_, SEMLB_PAIR_NAME)
#define SEMLB_PAIR_INSTANCE                                                                                   \
  inline void pair(semlb_real dx, semlb_real dy, semlb_real dz, int ii, int ij, uint64_t ki, uint64_t kj,     \
                   const semlb_real* p, semlb_real c2, int64_t* acc) {                                        \
    if (semlb_pair_force(dx, dy, dz, ii, ij, p, c2, acc) < 0) semlb_coincident_force(ki, kj, ii, ij, p, acc); \
  }

namespace semlb::engine::phys64::SEMLB_PAIR_NAME {
#include SEMLB_PAIR_HEADER
#include "pairs/pair_force.h"
SEMLB_PAIR_INSTANCE
}  // namespace semlb::engine::phys64::SEMLB_PAIR_NAME
namespace semlb::engine::phys32::SEMLB_PAIR_NAME {
#include SEMLB_PAIR_HEADER
#include "pairs/pair_force.h"
SEMLB_PAIR_INSTANCE
}  // namespace semlb::engine::phys32::SEMLB_PAIR_NAME
#undef SEMLB_PAIR_INSTANCE
#undef SEMLB_PAIR_LAW
#undef SEMLB_PAIR_CAT
#undef SEMLB_PAIR_CAT2
#undef SEMLB_PAIR_HEADER
#undef SEMLB_PAIR_NAME
