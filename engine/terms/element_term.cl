/* The loop of every element term (terms/term.hpp), one kernel per registered term: embed_kernels.cmake writes
 * this template once per terms/NAME.h after that header, with NAME for @TERM@. One work-item per owned element
 * adds the term's force in fixed point. */
/* A template that embed_kernels.cmake expands line by line (@NAME@ and the like are replaced by each registered
   name, so the spacing and the lines around them are its syntax, not layout): clang-format stays off it. */
/* clang-format off */
__kernel void @TERM@(__global const real4* pos, __constant const SEMLB_REAL* p, __global long* force, int n) {
  int i = get_global_id(0);
  if (i >= n) return;
  real4 q = pos[i];
  semlb_real f[3];
  semlb_term_@TERM@(q.x, q.y, q.z, semlb_info_type(INFO(q.w)), p, f);
  force[3 * i] += semlb_to_fixed(f[0]);
  force[3 * i + 1] += semlb_to_fixed(f[1]);
  force[3 * i + 2] += semlb_to_fixed(f[2]);
}
