/* "oriented": the size trigger of long_axis, but the split plane's normal is a fixed direction (p[2..4], a unit
 * vector) whatever the cell's shape: spindle orientation set by the tissue rather than the cell. With the normal
 * along z (the default), a basal cell divides perpendicular to the basement membrane and puts its daughter above it,
 * the asymmetric division by which the epidermis stratifies (Lechler & Fuchs 2005, Nature 437:275); along x or y it
 * divides in the plane (the symmetric, proliferative division). C99 subset, no include guard: included by
 * oriented.cpp (namespace cellrules) and pasted into the OpenCL cell section (division_rules.cl). Parameters
 * (doubles): (type mask, at_elements, nx, ny, nz). */
static inline int semlb_divides_oriented(int type, int count, const double* centroid, const double* p) {
  (void)centroid;
  return semlb_cell_divides_by_size(type, count, p);
}
static inline void semlb_division_axis_oriented(const double* g, const double* centroid, const double* p,
                                                double* axis) {
  (void)g;
  (void)centroid;
  for (int d = 0; d < 3; ++d) axis[d] = p[2 + d];
}
