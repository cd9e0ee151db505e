/* "relu": ya||a's piecewise-linear pair force (Germann, Marin-Riera & Sharpe 2019, "ya||a: GPU-powered spheroid models
 * for mesenchyme and epithelium", Cell Systems 8:261; its `relu_force`): f(r) = k_rep max(r0 - r, 0) - k_adh max(r -
 * r0, 0) for r < r_max, 0 beyond, positive repulsive: a linear spring around the equilibrium distance r0 that lets go
 * at r_max. The intra-cell set between elements of one cell, else the inter-cell set. C99 subset, no guard.
 * Parameters (reals): (k_rep, k_adh, r0, r_max) intra at 0, inter at 4. */
static inline semlb_real semlb_pair_relu(semlb_real r, int info_i, int info_j, SEMLB_CONST const semlb_real* p) {
  SEMLB_CONST const semlb_real* set = p + (info_i == info_j ? 0 : 4);
  if (r >= set[3]) return (semlb_real)0.0;
  return set[0] * SEMLB_FMAX(set[2] - r, (semlb_real)0.0) - set[1] * SEMLB_FMAX(r - set[2], (semlb_real)0.0);
}
