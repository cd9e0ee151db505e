/* The decomposition's arithmetic written once (C99 subset, no include guard): the slice of an x, the bin of a
 * coordinate, a slice's owner and the element count of the 27 bins around a bin (n_N of paper eq. 3), in double.
 * Used by model/slices.cpp (SliceMap::slice_of, Grid::bin_of, owner_of, cell_work) and by the W_s and
 * migration kernels of backends/cells.cl. The includer defines SEMLB_FLOOR (floor of a double) and SEMLB_GLOBAL
 * (the address space of the boundary and count arrays). */

/* floor(f) clamped into [0, n): NaN and below 0 -> 0, n and above -> n - 1. */
static inline int semlb_clamp_floor(double f, int n) { return !(f >= 0) ? 0 : (f >= n ? n - 1 : (int)f); }

/* The slice of x: slice s covers [x0 + s width, x0 + (s + 1) width) um, x outside clamped, NaN -> 0. */
static inline int semlb_slice_of(double x, double x0, double width, int slices) {
  return semlb_clamp_floor(SEMLB_FLOOR((x - x0) / width), slices);
}

/* The bin of coordinate x along one axis of a grid from lo with bins of `size`, `dims` of them (clamped). */
static inline int semlb_bin_of(double x, double lo, double size, int dims) {
  return semlb_clamp_floor(SEMLB_FLOOR((x - lo) / size), dims);
}

/* The rank owning `slice`: the number of the nb interior boundaries (ascending) at or below it. */
static inline int semlb_owner_of(int slice, SEMLB_GLOBAL const int* bounds, int nb) {
  int o = 0;
  for (int k = 0; k < nb; ++k) o += bounds[k] <= slice;
  return o;
}

/* Elements in the bins around bin (bx, by, bz) (3 x 3 x 3, clipped at the grid's faces) of a grid of nx x ny x nz
 * bins whose counts are stored z-major, x fastest. */
#include "stencil.h"
static inline long semlb_near_count(SEMLB_GLOBAL const int* counts, int bx, int by, int bz, int nx, int ny, int nz) {
  long near = 0;
  SEMLB_STENCIL_ROWS(bx, by, bz, nx, ny, nz, first, last)
  for (long b = first; b <= last; ++b) near += counts[b];
  return near;
}
