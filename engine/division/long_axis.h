/* "long_axis": a cell of a dividing type with at least at_elements elements splits through its centroid,
 * perpendicular to the long axis of its gyration tensor (Hertwig's rule: O. Hertwig 1884; as in ya||a's and Du et
 * al. 2018's epidermis). C99 subset, no include guard: included by long_axis.cpp (namespace cellrules) and pasted
 * into the OpenCL cell section (division_rules.cl). Parameters (doubles): (type mask, at_elements). */
static inline int semlb_divides_long_axis(int type, int count, const double* centroid, const double* p) {
  (void)centroid;
  return semlb_cell_divides_by_size(type, count, p);
}
static inline void semlb_division_axis_long_axis(const double* g, const double* centroid, const double* p,
                                                 double* axis) {
  (void)centroid;
  (void)p;
  semlb_cell_long_axis(g, axis);
}
