/* The neighbourhood of a bin (27 bins, or (2R + 1)^3 of smaller bins), written once (C99 subset) for every loop over
 * it: the pair-force stencils and the neighbour list's build (the OpenCL kernels), cpu-binned's pair loop, W_s's near
 * count (slices.h) and the bench's density statistics. */
#ifndef SEMLB_STENCIL_H
#define SEMLB_STENCIL_H

/* Runs the statement that follows once per row of the (2R + 1)^3 bins around bin (bx, by, bz) of an nx x ny x nz
 * grid (bins stored z-major, x fastest; rows clipped at the grid's faces: (2R + 1)^2 rows of 2R + 1 bins inside the
 * grid, fewer at a face), with FIRST and LAST (long) the row's first and last bin index: a row's bins are contiguous
 * in bin order, so a counting sort's starts[FIRST] .. starts[LAST + 1] are the row's elements. Bins of edge >= d / R
 * hold every element within d of one in bin (bx, by, bz) in these rows. */
#define SEMLB_STENCIL_ROWS_REACH(bx, by, bz, nx, ny, nz, R, FIRST, LAST)                                               \
  for (int semlb_z_ = (bz) >= (R) ? (bz) - (R) : 0; semlb_z_ <= ((bz) + (R) < (nz) ? (bz) + (R) : (nz)-1); ++semlb_z_) \
    for (int semlb_y_ = (by) >= (R) ? (by) - (R) : 0; semlb_y_ <= ((by) + (R) < (ny) ? (by) + (R) : (ny)-1);           \
         ++semlb_y_)                                                                                                   \
      for (long FIRST = ((long)semlb_z_ * (ny) + semlb_y_) * (nx) + ((bx) >= (R) ? (bx) - (R) : 0),                    \
                LAST = ((long)semlb_z_ * (ny) + semlb_y_) * (nx) + ((bx) + (R) < (nx) ? (bx) + (R) : (nx)-1),          \
                semlb_once_ = 1;                                                                                       \
           semlb_once_; semlb_once_ = 0)

/* The 27-bin neighbourhood (R = 1): bins of edge >= the cutoff. */
#define SEMLB_STENCIL_ROWS(bx, by, bz, nx, ny, nz, FIRST, LAST) \
  SEMLB_STENCIL_ROWS_REACH(bx, by, bz, nx, ny, nz, 1, FIRST, LAST)

#endif
