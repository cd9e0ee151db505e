// The evaluator header named by SEMLB_TERM_HEADER (a string literal) compiled for the C++ backends in both
// precisions, inside namespaces phys64 (double) and phys32 (float) of cpu_physics.hpp: a term's NAME.cpp defines
// SEMLB_TERM_HEADER "terms/NAME.h" and includes this file once, then registers phys64::semlb_term_NAME and
// phys32::semlb_term_NAME. No include guard: one inclusion per term file.
#include "physics/cpu_physics.hpp"

#ifndef SEMLB_TERM_HEADER
#error "define SEMLB_TERM_HEADER (the term's evaluator header) before including terms/instantiate.hpp"
#endif
namespace semlb::engine::phys64 {
#include SEMLB_TERM_HEADER
}  // namespace semlb::engine::phys64
namespace semlb::engine::phys32 {
#include SEMLB_TERM_HEADER
}  // namespace semlb::engine::phys32
#undef SEMLB_TERM_HEADER
