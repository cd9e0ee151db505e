/* The 27-bin neighbourhood of a bin, written once (C99 subset) for every loop over it: the pair-force stencils and
 * the neighbour list's build (the OpenCL kernels), cpu-binned's pair loop, W_s's near count (slices.h) and the bench's
 * density statistics. */
#ifndef SEMLB_STENCIL_H
#define SEMLB_STENCIL_H

/* Runs the statement that follows once per row of the 3 x 3 x 3 bins around bin (bx, by, bz) of an nx x ny x nz
 * grid (bins stored z-major, x fastest; rows clipped at the grid's faces: 9 rows of 3 bins inside the grid, fewer
 * at a face), with FIRST and LAST (long) the row's first and last bin index: a row's bins are contiguous in bin
 * order, so a counting sort's starts[FIRST] .. starts[LAST + 1] are the row's elements. */
#define SEMLB_STENCIL_ROWS(bx, by, bz, nx, ny, nz, FIRST, LAST)                                               \
  for (int semlb_z_ = (bz) > 0 ? (bz)-1 : 0; semlb_z_ <= ((bz) + 1 < (nz) ? (bz) + 1 : (nz)-1); ++semlb_z_)   \
    for (int semlb_y_ = (by) > 0 ? (by)-1 : 0; semlb_y_ <= ((by) + 1 < (ny) ? (by) + 1 : (ny)-1); ++semlb_y_) \
      for (long FIRST = ((long)semlb_z_ * (ny) + semlb_y_) * (nx) + ((bx) > 0 ? (bx)-1 : 0),                  \
                LAST = ((long)semlb_z_ * (ny) + semlb_y_) * (nx) + ((bx) + 1 < (nx) ? (bx) + 1 : (nx)-1),     \
                semlb_once_ = 1;                                                                              \
           semlb_once_; semlb_once_ = 0)

#endif
