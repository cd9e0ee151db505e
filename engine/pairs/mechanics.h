/* "mechanics": the SEM Morse law between elements (eq. 1's V_ele; Newman 2005, Math. Biosci. Eng. 2:613; Sandersius &
 * Newman 2008, Phys. Biol. 5:015002): V(r) = U0 exp(-r/xi1) - V0 exp(-r/xi2), so f(r) = -dV/dr = U0/xi1 exp(-r/xi1)
 * - V0/xi2 exp(-r/xi2), positive repulsive; the intra-cell set between elements of one cell, else the inter-cell
 * set of the two cells' types (selective adhesion). C99 subset, no guard (pairs/pair_force.h says why).
 * Parameters (reals): Morse sets stored as derived constants (U0/xi1, 1/xi1, V0/xi2, 1/xi2), computed on the host
 * (mechanics.cpp) so that the kernels divide nothing: the intra set at 0, the inter set of types (ti, tj) at
 * SEMLB_MORSE_INTER(ti, tj); SEMLB_MORSE_TABLE_SIZE in all. */
#define SEMLB_MORSE_TYPES 3
#define SEMLB_MORSE_INTRA 0
#define SEMLB_MORSE_INTER(ti, tj) (4 + 4 * ((ti)*SEMLB_MORSE_TYPES + (tj)))
#define SEMLB_MORSE_TABLE_SIZE (4 + 4 * SEMLB_MORSE_TYPES * SEMLB_MORSE_TYPES)

/* f(r) of one Morse set (SEMLB_PAIR_EXP: the OpenCL builds' backend.pair_exp, else SEMLB_EXP). */
static inline semlb_real semlb_morse_magnitude(semlb_real r, SEMLB_CONST const semlb_real* set) {
  return set[0] * SEMLB_PAIR_EXP(-r * set[1]) - set[2] * SEMLB_PAIR_EXP(-r * set[3]);
}

static inline semlb_real semlb_pair_mechanics(semlb_real r, int info_i, int info_j, SEMLB_CONST const semlb_real* p) {
  int set = info_i == info_j ? SEMLB_MORSE_INTRA : SEMLB_MORSE_INTER(semlb_info_type(info_i), semlb_info_type(info_j));
  return semlb_morse_magnitude(r, p + set);
}
