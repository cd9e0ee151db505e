/* "walls": lateral confinement by planes x = xlo, x = xhi, y = ylo, y = yhi (um), each pushing every element toward
 * the inside with the SEM Morse form of the basement membrane (membrane.h; Newman 2005, Math. Biosci. Eng. 2:613)
 * along its normal: f(d) = U/xi_U exp(-d/xi_U) - V/xi_V exp(-d/xi_V) at distance d inside the face, as LAMMPS's
 * `fix wall/morse` puts a Morse wall on the faces xlo ... yhi. C99 subset, no guard (membrane.h says why).
 * Parameters (reals): (U/xi_U, 1/xi_U, V/xi_V, 1/xi_V, xlo, xhi, ylo, yhi); a face that is absent sits at -+1e30,
 * where its force is exp(-inf) = 0. Each component is clamped (semlb_clamp_force). */
static inline semlb_real semlb_walls_morse(semlb_real d, SEMLB_CONST const semlb_real* w) {
  return w[0] * SEMLB_EXP(-d * w[1]) - w[2] * SEMLB_EXP(-d * w[3]);
}
static inline void semlb_term_walls(semlb_real x, semlb_real y, semlb_real z, int type, SEMLB_CONST const semlb_real* w,
                                    semlb_real* f) {
  (void)z;
  (void)type;
  f[0] = semlb_clamp_force(semlb_walls_morse(x - w[4], w) - semlb_walls_morse(w[5] - x, w));
  f[1] = semlb_clamp_force(semlb_walls_morse(y - w[6], w) - semlb_walls_morse(w[7] - y, w));
  f[2] = (semlb_real)0.0;
}
