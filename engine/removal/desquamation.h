/* "desquamation": a cell whose centroid is above `height` um is shed, as the cornified layer of the epidermis is
 * (Miller, Crampin & Osborne 2022, "Multiscale modelling of desquamation in the interfollicular epidermis",
 * PLoS Comput Biol 18:e1010368, models the same loss of the outermost cells). C99 subset, no include guard:
 * included by desquamation.cpp (namespace cellrules) and pasted into the OpenCL cell section (removal_rule.cl).
 * Parameters (doubles): (height). */
static inline int semlb_remove_desquamation(double cx, double cy, double cz, int type, int count,
                                            SEMLB_CONST const double* p) {
  (void)cx;
  (void)cy;
  (void)type;
  (void)count;
  return cz > p[0];
}
