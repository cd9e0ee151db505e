/* The dispatch over every growth law (growth/growth_law.hpp): embed_kernels.cmake writes this template once, after
 * the laws' headers, with each line that names @NAME@ repeated per law in name order, @INDEX@ its index (the host's
 * index in growth_law_names(): semlb_cell_rules.growth). A uniform branch: every cell of a launch takes one case. */
/* A template that embed_kernels.cmake expands line by line (@NAME@ and the like are replaced by each registered
   name, so the spacing and the lines around them are its syntax, not layout): clang-format stays off it. */
/* clang-format off */
static inline int semlb_growth_law(int law, int type, int count, const double* centroid, double time, double elapsed,
                                   const double* p, double* field) {
  switch (law) {
    case @INDEX@: return semlb_growth_@NAME@(type, count, centroid, time, elapsed, p, field);
  }
  return 0;
}
