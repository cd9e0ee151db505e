/* OpenCL kernels of the opencl-allpairs and opencl-binned backends; the physics comes from evaluator.h. */
#pragma OPENCL FP_CONTRACT OFF
#ifdef SEMLB_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define SEMLB_REAL double
typedef double4 real4;
#define INFO(w) ((int)as_long(w))
#else
#define SEMLB_REAL float
typedef float4 real4;
#define INFO(w) as_int(w)
#endif
#define SEMLB_LONG long
#define SEMLB_ULONG ulong
#define SEMLB_CONST __constant
#define SEMLB_EXP exp
#define SEMLB_SQRT sqrt
#define SEMLB_LOG log
#define SEMLB_COS cos
#define SEMLB_FMIN fmin
#define SEMLB_FMAX fmax
/* The pair force law's exp (backend.pair_exp, docs/engine.md "Pair exp"): float builds native_exp unless
   -DSEMLB_PAIR_EXP_BUILTIN; double builds the built-in exp, semlb_exp_ranged (physics/exp.h) with
   -DSEMLB_PAIR_EXP_RANGED, or float's native_exp with -DSEMLB_PAIR_EXP_NATIVE. */
#ifndef SEMLB_DOUBLE /* native math in the pair force law of float builds (docs/engine.md: error and gain) */
#ifndef SEMLB_PAIR_EXP_BUILTIN
#define SEMLB_PAIR_EXP native_exp
#endif
#define SEMLB_PAIR_RSQRT native_rsqrt
#else
#define SEMLB_BITS as_ulong
#define SEMLB_FROM_BITS as_double
#include "exp.h"
#ifdef SEMLB_PAIR_EXP_RANGED
#define SEMLB_PAIR_EXP semlb_exp_ranged
#elif defined(SEMLB_PAIR_EXP_NATIVE)
#define SEMLB_PAIR_EXP(x) ((double)native_exp((float)(x)))
#endif
#ifdef SEMLB_DOUBLE_RSQRT /* a variant: r and 1/r from one double rsqrt (<= 2 ulp) instead of sqrt and a division */
#define SEMLB_PAIR_RSQRT rsqrt
#endif
#endif
#include "evaluator.h"

/* The pair terms' laws (pairs/NAME.h, every registered one); the program is built for one,
   -DSEMLB_PAIR_TERM=semlb_pair_NAME (pairs/pair_term.hpp), whose law the pair loop's body calls. */
#include "pair_terms.cl"
#ifndef SEMLB_PAIR_TERM
#error "build with -DSEMLB_PAIR_TERM=semlb_pair_NAME (pairs/pair_term.hpp)"
#endif
#define SEMLB_PAIR_LAW SEMLB_PAIR_TERM
#include "pair_force.h"

#define NO_FAILURE 0x7fffffff

#include "stencil.h"

#include "bins.cl"
#include "pair_forces.cl"
#include "neighbour_list.cl"

/* The element terms (terms/NAME.h), each followed by its kernel from terms/element_term.cl. */
#include "element_terms.cl"

#include "elements.cl"
#include "cells.cl"
