/* The pair loop's force on element i from element j, written once over one pair term's law (C99 subset, no include
 * guard: included once per pair term in C++, pairs/instantiate.hpp, and once in the OpenCL program, kernels.cl).
 * The includer defines SEMLB_PAIR_LAW, the term's evaluator `semlb_real semlb_pair_NAME(semlb_real r, int info_i,
 * int info_j, SEMLB_CONST const semlb_real* p)` (pairs/pair_term.hpp), after evaluator.h. */

/* The bound acc[3] of a sum: each pair adds floor(min(|f|, SEMLB_FORCE_MAX)) + 1 (force units; a NaN f counts as
 * the maximum), at least |F_ij| / 2^32 of each of its three fixed-point components (an integer, so its sum does not
 * depend on the order). While an element's bound, all its contributions together, stays below SEMLB_BOUND_LIMIT
 * (2^30, half of the 2^31 force units an int64 of 2^-32 units holds, so rounding in |d_k| / r cannot matter) no
 * fixed-point force sum of it can leave int64; beyond it the integrator stops the run (Failure code 3). */
#ifndef SEMLB_PAIR_BOUND
#define SEMLB_PAIR_BOUND(f) ((SEMLB_LONG)SEMLB_FMIN(SEMLB_FMAX((f), -(f)), (semlb_real)SEMLB_FORCE_MAX) + 1)
#endif

/* The pair's law for r2 = |d|^2 below the cutoff: *f = f(r) and *s = f(r) / r * 2^32 (the fixed-point scale folded
 * into the magnitude). Returns 1, or -1 for coincident elements (r < SEMLB_R_MIN), whose direction is undefined. */
static inline int semlb_pair_scale(semlb_real r2, int info_i, int info_j, SEMLB_CONST const semlb_real* p,
                                   semlb_real* f, semlb_real* s) {
#ifdef SEMLB_PAIR_RSQRT
  if (r2 < (semlb_real)SEMLB_R_MIN2) return -1;
  semlb_real inv = SEMLB_PAIR_RSQRT(r2), r = r2 * inv;
  *f = SEMLB_PAIR_LAW(r, info_i, info_j, p);
  *s = *f * inv * (semlb_real)SEMLB_FIXED_SCALE;
#else
  semlb_real r = SEMLB_SQRT(r2);
  if (r < (semlb_real)SEMLB_R_MIN) return -1;
  *f = SEMLB_PAIR_LAW(r, info_i, info_j, p);
  *s = *f / r * (semlb_real)SEMLB_FIXED_SCALE;
#endif
  return 1;
}

/* Force on element i from element j, added to acc[0..2] in fixed point, and its bound to acc[3]; d = Y_i - Y_j
 * (eq. 1: the force along d is the law's f(r) = -dV/dr, positive repulsive). Returns 0 outside the cutoff, 1 when
 * added, and -1 for coincident elements (r < SEMLB_R_MIN), whose direction is undefined: the caller then calls
 * semlb_coincident_force. A NaN distance counts as within the cutoff (it reaches the force and the integrator
 * reports it). */
static inline int semlb_pair_force(semlb_real dx, semlb_real dy, semlb_real dz, int info_i, int info_j,
                                   SEMLB_CONST const semlb_real* p, semlb_real cutoff2, SEMLB_LONG* acc) {
  semlb_real r2 = dx * dx + dy * dy + dz * dz, f, s;
  if (r2 >= cutoff2) return 0;
  if (semlb_pair_scale(r2, info_i, info_j, p, &f, &s) < 0) return -1;
  acc[0] += semlb_scaled_to_fixed(s * dx);
  acc[1] += semlb_scaled_to_fixed(s * dy);
  acc[2] += semlb_scaled_to_fixed(s * dz);
  acc[3] += SEMLB_PAIR_BOUND(f);
  return 1;
}

/* Newton's third law (LAMMPS's `newton on` for pairs): semlb_pair_force's force on i into acc_i, and the same pair's
 * force on j into acc_j, each component the fixed point of the negated product. Since -(s dx) = s (-dx) exactly and
 * the law is symmetric in (info_i, info_j) (every registered one is: pairs/pair_term.hpp), acc_j receives what
 * semlb_pair_force(-d, info_j, info_i) adds, bit for bit, a NaN included. Same returns; on -1 the caller calls
 * semlb_coincident_force for each side. */
static inline int semlb_pair_force_newton(semlb_real dx, semlb_real dy, semlb_real dz, int info_i, int info_j,
                                          SEMLB_CONST const semlb_real* p, semlb_real cutoff2, SEMLB_LONG* acc_i,
                                          SEMLB_LONG* acc_j) {
  semlb_real r2 = dx * dx + dy * dy + dz * dz, f, s;
  if (r2 >= cutoff2) return 0;
  if (semlb_pair_scale(r2, info_i, info_j, p, &f, &s) < 0) return -1;
  semlb_real fx = s * dx, fy = s * dy, fz = s * dz;
  SEMLB_LONG bound = SEMLB_PAIR_BOUND(f);
  acc_i[0] += semlb_scaled_to_fixed(fx);
  acc_i[1] += semlb_scaled_to_fixed(fy);
  acc_i[2] += semlb_scaled_to_fixed(fz);
  acc_i[3] += bound;
  acc_j[0] += semlb_scaled_to_fixed(-fx);
  acc_j[1] += semlb_scaled_to_fixed(-fy);
  acc_j[2] += semlb_scaled_to_fixed(-fz);
  acc_j[3] += bound;
  return 1;
}

/* Coincident elements are pushed apart with f(0) along a unit vector hashed from the two keys, with
 * opposite signs for i and j, so that F_ij = -F_ji exactly and the result is order-independent. */
static inline void semlb_coincident_force(SEMLB_ULONG key_i, SEMLB_ULONG key_j, int info_i, int info_j,
                                          SEMLB_CONST const semlb_real* p, SEMLB_LONG* acc) {
  semlb_real f = SEMLB_PAIR_LAW((semlb_real)0.0, info_i, info_j, p);
  SEMLB_ULONG lo = key_i < key_j ? key_i : key_j, hi = key_i < key_j ? key_j : key_i;
  semlb_real sign = key_i < key_j ? (semlb_real)-1.0 : (semlb_real)1.0;
  semlb_real ux = semlb_gauss(lo, hi, 0, 0), uy = semlb_gauss(lo, hi, 0, 1), uz = semlb_gauss(lo, hi, 0, 2);
  semlb_real s = sign * f / (SEMLB_SQRT(ux * ux + uy * uy + uz * uz) + (semlb_real)1e-30);
  acc[0] += semlb_to_fixed(s * ux);
  acc[1] += semlb_to_fixed(s * uy);
  acc[2] += semlb_to_fixed(s * uz);
  acc[3] += SEMLB_PAIR_BOUND(f);
}
