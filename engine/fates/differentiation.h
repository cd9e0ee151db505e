/* "differentiation": a basal cell (type 0) whose centroid rises above `basal_height` um (it lost the basement membrane)
 * becomes spinous (1); a spinous cell becomes granular (2) `granular_after` h later; a change resets the age (its
 * per-cell field differentiation.age, h). The epidermal differentiation sequence of Du et al. 2018 ("Multiscale
 * modeling of layer formation in epidermis", PLoS Comput Biol 14:e1006006). C99 subset, no include guard: included
 * by differentiation.cpp (namespace cellrules) and pasted into the OpenCL cell section (fate_rule.cl).
 * Parameters (doubles): (basal_height, granular_after). */
static inline int semlb_fate_differentiation(double cx, double cy, double cz, int count, double elapsed,
                                             SEMLB_CONST const double* p, int* type, double* age) {
  (void)cx;
  (void)cy;
  (void)count;
  *age += elapsed;
  int next = *type;
  if (next == 0 && cz > p[0])
    next = 1;
  else if (next == 1 && *age >= p[1])
    next = 2;
  if (next == *type) return 0;
  *type = next;
  *age = 0;
  return 1;
}
