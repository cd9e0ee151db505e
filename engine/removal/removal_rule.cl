/* The flags of every removal rule (removal/removal.hpp), one kernel per registered rule: embed_kernels.cmake
 * writes this template once per removal/NAME.h after that header, with NAME for @RULE@, inside the fp64 cell
 * section. Per cell, as cells_owner does for the migration: leave[c] the rule's verdict on its centroid, type and
 * element count, owner[c] = -1, its elements counted among the leavers' (elems[c]) or the stayers' (elems[n + c]);
 * cells_split then compacts the stayers. */
/* A template that embed_kernels.cmake expands line by line (@NAME@ and the like are replaced by each registered
   name, so the spacing and the lines around them are its syntax, not layout): clang-format stays off it. */
/* clang-format off */
__kernel void remove_@RULE@(int n, __global const real4* pos, __global const int* first, __global const int* count,
                            __global const int* type, __constant const double* p, __global int* leave,
                            __global int* owner, __global int* elems) {
  int c = get_global_id(0);
  if (c >= n) return;
  double ctr[3];
  semlb_cell_centroid(pos, first[c], count[c], ctr);
  int l = semlb_remove_@RULE@(ctr[0], ctr[1], ctr[2], type[c], count[c], p) != 0;
  owner[c] = -1;
  leave[c] = l;
  elems[c] = l ? count[c] : 0;
  elems[n + c] = l ? 0 : count[c];
}
