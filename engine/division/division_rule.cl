/* The dispatches over every division rule (division/division_rule.hpp): embed_kernels.cmake writes this template
 * once, after the rules' headers, with each line that names @NAME@ repeated per rule in name order, @INDEX@ its index
 * (the host's index in division_rule_names(): semlb_cell_rules.division). Uniform branches. */
/* A template that embed_kernels.cmake expands line by line (@NAME@ and the like are replaced by each registered
   name, so the spacing and the lines around them are its syntax, not layout): clang-format stays off it. */
/* clang-format off */
static inline int semlb_divides(int rule, int type, int count, const double* centroid, const double* p) {
  switch (rule) {
    case @INDEX@: return semlb_divides_@NAME@(type, count, centroid, p);
  }
  return 0;
}
static inline void semlb_division_axis(int rule, const double* g, const double* centroid, const double* p, double* axis) {
  switch (rule) {
    case @INDEX@: semlb_division_axis_@NAME@(g, centroid, p, axis); return;
  }
}
