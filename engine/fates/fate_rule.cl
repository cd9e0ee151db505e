/* The loop of every fate rule (fates/fate.hpp), one kernel per registered rule: embed_kernels.cmake writes this
 * template once per fates/NAME.h after that header, with NAME for @FATE@, inside the fp64 cell section. Per cell of
 * the stage's new state: the rule on its centroid, element count and field (record index `field`, -1: none); a new
 * type is written into the cell and its elements. */
/* A template that embed_kernels.cmake expands line by line (@NAME@ and the like are replaced by each registered
   name, so the spacing and the lines around them are its syntax, not layout): clang-format stays off it. */
/* clang-format off */
__kernel void fate_@FATE@(int n, double elapsed, __constant const double* p, int field, int nf, __global real4* pos,
                          __global const int* first, __global const int* count, __global int* type,
                          __global double* fields) {
  int c = get_global_id(0);
  if (c >= n) return;
  __global double* rec = CELL_RECORD(fields, nf, c);
  double ctr[3], f = cell_field(rec, field);
  int t = type[c];
  semlb_cell_centroid(pos, first[c], count[c], ctr);
  int changed = semlb_fate_@FATE@(ctr[0], ctr[1], ctr[2], count[c], elapsed, p, &t, &f);
  if (field >= 0) rec[field] = f;
  if (!changed) return;
  type[c] = t;
  for (int k = 0; k < count[c]; ++k) pos[first[c] + k].w = CELL_INFO(semlb_info_pack(c, t));
}
