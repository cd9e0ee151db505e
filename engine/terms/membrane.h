/* "membrane": the basement membrane at z = 0 (V_ext of the paper's eq. 1; docs/engine.md "Physics"): a repulsive
 * exponential wall for every element and exponential adhesion for basal elements (type 0). C99 subset, no guard:
 * included once per precision by membrane.cpp and inlined into the OpenCL kernels (element_term.cl).
 * Parameters (reals), derived like a Morse set: (U_wall/xi_wall, 1/xi_wall, V_adh/xi_adh, 1/xi_adh). */
static inline void semlb_term_membrane(semlb_real x, semlb_real y, semlb_real z, int type,
                                       SEMLB_CONST const semlb_real* m, semlb_real* f) {
  semlb_real fz = m[0] * SEMLB_EXP(-z * m[1]);
  if (type == 0) fz -= m[2] * SEMLB_EXP(-z * m[3]);
  (void)x;
  (void)y;
  f[0] = (semlb_real)0.0;
  f[1] = (semlb_real)0.0;
  f[2] = semlb_clamp_force(fz);
}
