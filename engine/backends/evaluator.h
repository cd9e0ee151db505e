/* The SEM physics written once (C99 subset): included by the C++ backends and by the OpenCL kernels. */
/* No include guard on purpose: C++ includes it once per precision inside a namespace. The includer
 * defines SEMLB_REAL (float|double), SEMLB_LONG / SEMLB_ULONG (64-bit integers), SEMLB_CONST (the
 * address space of parameter tables), SEMLB_EXP and SEMLB_SQRT, SEMLB_LOG, SEMLB_COS, and SEMLB_FMIN / SEMLB_FMAX
 * (IEEE minNum / maxNum: of a NaN and a number, the number). Optional: SEMLB_PAIR_EXP
 * (the exp of the pair force law; default SEMLB_EXP) and SEMLB_PAIR_RSQRT (then r and 1/r of a pair come from
 * one reciprocal square root instead of a sqrt and a division; coincidence is then r^2 < SEMLB_R_MIN^2): the
 * OpenCL float build uses them for native math.
 * Equations: docs/engine.md; eq. (1) of the paper is dY/dt = -grad sum V_ele - grad V_ext. */

typedef SEMLB_REAL semlb_real;
#ifndef SEMLB_PAIR_EXP
#define SEMLB_PAIR_EXP SEMLB_EXP
#endif

/* Forces are summed in fixed point (2^-32 force units) so that sums do not depend on their order. */
#define SEMLB_FIXED_SCALE 4294967296.0
#define SEMLB_FIXED_INV (1.0 / 4294967296.0)
/* Per-pair and per-element force clamp (force units) keeping every fixed-point sum inside int64. */
#define SEMLB_FORCE_MAX 1048576.0
/* Below this distance (length units) the pair direction is taken from the element keys (r = 0). */
#define SEMLB_R_MIN 1e-6
#define SEMLB_R_MIN2 1e-12 /* SEMLB_R_MIN^2 as one literal (the device compiler did not fold the product) */

/* Parameter table layout (reals): a Morse set is stored as derived constants (U0/xi1, 1/xi1, V0/xi2, 1/xi2),
 * computed on the host from the scene's U0, V0, xi1, xi2, so that the kernels divide nothing. */
#define SEMLB_TYPES 3
#define SEMLB_MORSE_INTRA 0                     /* the intra-cell set */
#define SEMLB_MORSE_INTER(ti, tj) (4 + 4 * ((ti) * SEMLB_TYPES + (tj)))
#define SEMLB_TABLE_SIZE (4 + 4 * SEMLB_TYPES * SEMLB_TYPES)

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
static inline SEMLB_LONG semlb_to_fixed(semlb_real f) { return semlb_scaled_to_fixed(f * (semlb_real)SEMLB_FIXED_SCALE); }

/* f(r) = -dV/dr = U0/xi1 exp(-r/xi1) - V0/xi2 exp(-r/xi2) for V(r) = U0 exp(-r/xi1) - V0 exp(-r/xi2);
 * positive is repulsive. */
static inline semlb_real semlb_morse_magnitude(semlb_real r, SEMLB_CONST const semlb_real* set) {
  return set[0] * SEMLB_PAIR_EXP(-r * set[1]) - set[2] * SEMLB_PAIR_EXP(-r * set[3]);
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
#define SEMLB_DEFINE_RANDOM(T, UNIFORM, GAUSS)                                                                 \
  static inline T UNIFORM(SEMLB_ULONG seed, SEMLB_ULONG key, SEMLB_ULONG step, SEMLB_ULONG stream) {           \
    SEMLB_ULONG z = semlb_mix(semlb_mix(semlb_mix(seed ^ (stream << 56)) ^ key) ^ step);                      \
    return (T)((double)((z >> 11) + 1) * (1.0 / 9007199254740992.0));                                        \
  }                                                                                                          \
  static inline T GAUSS(SEMLB_ULONG seed, SEMLB_ULONG key, SEMLB_ULONG step, SEMLB_ULONG stream) {             \
    T u1 = UNIFORM(seed, key, step, 2 * stream);                                                             \
    T u2 = UNIFORM(seed, key, step, 2 * stream + 1);                                                         \
    return SEMLB_SQRT((T)-2.0 * SEMLB_LOG(u1)) * SEMLB_COS((T)6.283185307179586 * u2);                       \
  }
SEMLB_DEFINE_RANDOM(semlb_real, semlb_uniform, semlb_gauss)

/* Force on element i from element j, added to acc[0..2] in fixed point; d = Y_i - Y_j (eq. 1 with the
 * Morse V_ele of docs/engine.md). Returns 0 outside the cutoff, 1 when added, and -1 for coincident
 * elements (r < SEMLB_R_MIN), whose direction is undefined: the caller then calls semlb_coincident_force. */
static inline int semlb_pair_force(semlb_real dx, semlb_real dy, semlb_real dz, int info_i, int info_j,
                                   SEMLB_CONST const semlb_real* table, semlb_real cutoff2, SEMLB_LONG* acc) {
  semlb_real r2 = dx * dx + dy * dy + dz * dz;
  if (r2 >= cutoff2) return 0;
#ifdef SEMLB_PAIR_RSQRT
  if (r2 < (semlb_real)SEMLB_R_MIN2) return -1;
  semlb_real inv = SEMLB_PAIR_RSQRT(r2), r = r2 * inv;
#else
  semlb_real r = SEMLB_SQRT(r2);
  if (r < (semlb_real)SEMLB_R_MIN) return -1;
#endif
  int set = info_i == info_j ? SEMLB_MORSE_INTRA : SEMLB_MORSE_INTER(semlb_info_type(info_i), semlb_info_type(info_j));
#ifdef SEMLB_PAIR_RSQRT
  semlb_real s = semlb_morse_magnitude(r, table + set) * inv * (semlb_real)SEMLB_FIXED_SCALE;
#else
  semlb_real s = semlb_morse_magnitude(r, table + set) / r * (semlb_real)SEMLB_FIXED_SCALE;
#endif
  acc[0] += semlb_scaled_to_fixed(s * dx);
  acc[1] += semlb_scaled_to_fixed(s * dy);
  acc[2] += semlb_scaled_to_fixed(s * dz);
  return 1;
}

/* Coincident elements are pushed apart with f(0) along a unit vector hashed from the two keys, with
 * opposite signs for i and j, so that F_ij = -F_ji exactly and the result is order-independent. */
static inline void semlb_coincident_force(SEMLB_ULONG key_i, SEMLB_ULONG key_j, int info_i, int info_j,
                                          SEMLB_CONST const semlb_real* table, SEMLB_LONG* acc) {
  int set = info_i == info_j ? SEMLB_MORSE_INTRA : SEMLB_MORSE_INTER(semlb_info_type(info_i), semlb_info_type(info_j));
  semlb_real f = semlb_morse_magnitude((semlb_real)0.0, table + set);
  SEMLB_ULONG lo = key_i < key_j ? key_i : key_j, hi = key_i < key_j ? key_j : key_i;
  semlb_real sign = key_i < key_j ? (semlb_real)-1.0 : (semlb_real)1.0;
  semlb_real ux = semlb_gauss(lo, hi, 0, 0), uy = semlb_gauss(lo, hi, 0, 1), uz = semlb_gauss(lo, hi, 0, 2);
  semlb_real s = sign * f / (SEMLB_SQRT(ux * ux + uy * uy + uz * uz) + (semlb_real)1e-30);
  acc[0] += semlb_to_fixed(s * ux);
  acc[1] += semlb_to_fixed(s * uy);
  acc[2] += semlb_to_fixed(s * uz);
}

/* Overdamped Euler update of one coordinate: dY = dt/eta * F (eq. 1). */
static inline semlb_real semlb_displacement(SEMLB_LONG fixed_force, semlb_real dt_over_eta) {
  return dt_over_eta * ((semlb_real)fixed_force * (semlb_real)SEMLB_FIXED_INV);
}
