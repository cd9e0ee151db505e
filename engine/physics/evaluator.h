/* The SEM physics written once (C99 subset): included by the C++ backends and by the OpenCL kernels. */
/* No include guard on purpose: C++ includes it once per precision inside a namespace. The includer
 * defines SEMLB_REAL (float|double), SEMLB_LONG / SEMLB_ULONG (64-bit integers), SEMLB_CONST (the
 * address space of parameter tables), SEMLB_EXP and SEMLB_SQRT, SEMLB_LOG, SEMLB_COS, and SEMLB_FMIN / SEMLB_FMAX
 * (IEEE minNum / maxNum: of a NaN and a number, the number). Optional: SEMLB_PAIR_EXP
 * (the exp of the pair force law; default SEMLB_EXP) and SEMLB_PAIR_RSQRT (then r and 1/r of a pair come from
 * one reciprocal square root instead of a sqrt and a division; coincidence is then r^2 < SEMLB_R_MIN^2): the
 * OpenCL builds set them (kernels.cl: backend.pair_exp, and float's native rsqrt).
 * The pair force's loop body over a pair term's law is pairs/pair_force.h, beside the terms' laws (pairs/NAME.h).
 * Equations: docs/engine.md; eq. (1) of the paper is dY/dt = -grad sum V_ele - grad V_ext. */

typedef SEMLB_REAL semlb_real;
#ifndef SEMLB_PAIR_EXP
#define SEMLB_PAIR_EXP SEMLB_EXP
#endif

/* Forces are summed in fixed point (2^-32 force units) so that sums do not depend on their order. */
#define SEMLB_FIXED_SCALE 4294967296.0
#define SEMLB_FIXED_INV (1.0 / 4294967296.0)
/* Per-pair and per-element-term force clamp (force units): one contribution is at most 2^52 in fixed point. */
#define SEMLB_FORCE_MAX 1048576.0
/* The most an element's bound (pair_force.h: the sum over its contributions of floor(min(|f|, SEMLB_FORCE_MAX)) + 1,
 * force units) may reach: its fixed-point sums then stay below 2^31 force units = 2^63, inside int64, with a factor 2
 * to spare for rounding. Beyond it the integrator stops the run (code 3) rather than move by a wrapped sum. */
#define SEMLB_BOUND_LIMIT ((SEMLB_LONG)1 << 30)
/* The bound of one element term's contribution (each component clamped to SEMLB_FORCE_MAX). */
#define SEMLB_TERM_BOUND ((SEMLB_LONG)1048576 + 1)
/* Below this distance (length units) the pair direction is taken from the element keys (r = 0). */
#define SEMLB_R_MIN 1e-6
#define SEMLB_R_MIN2 1e-12 /* SEMLB_R_MIN^2 as one literal (the device compiler did not fold the product) */

/* An element's packed info: cell index (within the local state) << 2 | cell type (0..3). */
static inline int semlb_info_pack(int cell, int type) { return cell << 2 | type; }
static inline int semlb_info_cell(int info) { return info >> 2; }
static inline int semlb_info_type(int info) { return info & 3; }

/* f clamped to [-SEMLB_FORCE_MAX, SEMLB_FORCE_MAX]; NaN gives +SEMLB_FORCE_MAX (a huge step that integrate
 * reports). Two min/max instructions: minNum(NaN, M) = M. */
static inline semlb_real semlb_clamp_force(semlb_real f) {
  return SEMLB_FMAX(SEMLB_FMIN(f, (semlb_real)SEMLB_FORCE_MAX), -(semlb_real)SEMLB_FORCE_MAX);
}

/* A force component already multiplied by SEMLB_FIXED_SCALE, clamped to +-SEMLB_FORCE_MAX (scaled; NaN gives
 * +max), in fixed point (truncation toward zero, identical in C++ and OpenCL C). The pair force law folds the
 * scale into its magnitude; scaling by 2^32 is exact, so clamping before or after it gives the same value. */
static inline SEMLB_LONG semlb_scaled_to_fixed(semlb_real fs) {
  const semlb_real m = (semlb_real)(SEMLB_FORCE_MAX * SEMLB_FIXED_SCALE);
  return (SEMLB_LONG)SEMLB_FMAX(SEMLB_FMIN(fs, m), -m);
}

/* One force component in fixed point. */
static inline SEMLB_LONG semlb_to_fixed(semlb_real f) {
  return semlb_scaled_to_fixed(f * (semlb_real)SEMLB_FIXED_SCALE);
}

/* SplitMix64 finaliser: the counter-based generator shared by noise, growth and the tissue generator. */
static inline SEMLB_ULONG semlb_mix(SEMLB_ULONG z) {
  z += (SEMLB_ULONG)0x9E3779B97F4A7C15UL;
  z = (z ^ (z >> 30)) * (SEMLB_ULONG)0xBF58476D1CE4E5B9UL;
  z = (z ^ (z >> 27)) * (SEMLB_ULONG)0x94D049BB133111EBUL;
  return z ^ (z >> 31);
}

/* Uniform in (0, 1] from the counter (seed, key, step, stream), and a standard normal by Box-Muller from
 * two counter streams, in type T: semlb_uniform / semlb_gauss in semlb_real here; cells.h defines the
 * double ones of the cell stage with the same macro. */
#define SEMLB_DEFINE_RANDOM(T, UNIFORM, GAUSS)                                                       \
  static inline T UNIFORM(SEMLB_ULONG seed, SEMLB_ULONG key, SEMLB_ULONG step, SEMLB_ULONG stream) { \
    SEMLB_ULONG z = semlb_mix(semlb_mix(semlb_mix(seed ^ (stream << 56)) ^ key) ^ step);             \
    return (T)((double)((z >> 11) + 1) * (1.0 / 9007199254740992.0));                                \
  }                                                                                                  \
  static inline T GAUSS(SEMLB_ULONG seed, SEMLB_ULONG key, SEMLB_ULONG step, SEMLB_ULONG stream) {   \
    T u1 = UNIFORM(seed, key, step, 2 * stream);                                                     \
    T u2 = UNIFORM(seed, key, step, 2 * stream + 1);                                                 \
    return SEMLB_SQRT((T)-2.0 * SEMLB_LOG(u1)) * SEMLB_COS((T)6.283185307179586 * u2);               \
  }
SEMLB_DEFINE_RANDOM(semlb_real, semlb_uniform, semlb_gauss)

/* Overdamped Euler update of one coordinate: dY = dt/eta * F (eq. 1). */
static inline semlb_real semlb_displacement(SEMLB_LONG fixed_force, semlb_real dt_over_eta) {
  return dt_over_eta * ((semlb_real)fixed_force * (semlb_real)SEMLB_FIXED_INV);
}
