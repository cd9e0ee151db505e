/* OpenCL kernels of the opencl-allpairs and opencl-binned backends; the physics comes from evaluator.h. */
#pragma OPENCL FP_CONTRACT OFF
#ifdef SEMLB_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define SEMLB_REAL double
typedef double4 real4;
#define INFO(w) ((int)as_long(w))
#else
#define SEMLB_REAL float
typedef float4 real4;
#define INFO(w) as_int(w)
#endif
#define SEMLB_LONG long
#define SEMLB_ULONG ulong
#define SEMLB_CONST __constant
#define SEMLB_EXP exp
#define SEMLB_SQRT sqrt
#define SEMLB_LOG log
#define SEMLB_COS cos
#ifndef SEMLB_DOUBLE /* native math in the pair force law of float builds (docs/engine.md: error and gain) */
#define SEMLB_PAIR_EXP native_exp
#define SEMLB_PAIR_RSQRT native_rsqrt
#endif
#include "evaluator.h"

#define NO_FAILURE 0x7fffffff

/* Bin coordinates clamped into the grid (x fastest); clamped as reals first, so NaN lands in bin 0. */
static inline int bin1(SEMLB_REAL x, SEMLB_REAL lo, SEMLB_REAL size, int dim) {
  return (int)fmin(fmax(floor((x - lo) / size), (SEMLB_REAL)0), (SEMLB_REAL)(dim - 1));
}
static inline int4 bin3(real4 p, real4 lo, real4 size, int4 dims) {
  return (int4)(bin1(p.x, lo.x, size.x, dims.x), bin1(p.y, lo.y, size.y, dims.y), bin1(p.z, lo.z, size.z, dims.z), 0);
}

/* Elements [first, first + n): bin[k] the bin of element first + k; counts[bin] incremented. */
__kernel void bin_count(__global const real4* pos, int first, int n, real4 lo, real4 size, int4 dims, __global int* bin,
                        __global int* counts) {
  int i = get_global_id(0);
  if (i >= n) return;
  int4 b = bin3(pos[first + i], lo, size, dims);
  int k = (b.z * dims.y + b.y) * dims.x + b.x;
  bin[i] = k;
  atomic_inc(&counts[k]);
}

/* Inclusive Hillis-Steele scan of tmp[0..w) in local memory (all items of the group call it). */
static inline void scan_local(__local int* tmp, int l, int w) {
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int off = 1; off < w; off <<= 1) {
    int add = l >= off ? tmp[l - off] : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    tmp[l] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}

/* Exclusive scan, step 1: within blocks of the work-group size (power of two, <= 1024). */
__kernel void scan_blocks(__global const int* gate, __global const int* counts, __global int* starts, __global int* sums,
                          int nbins, __local int* tmp) {
  if (!gate[0]) return;  /* gate: the scan kernels run only when its first int is set (neighbour_list.cl) */
  int g = get_global_id(0), l = get_local_id(0), w = get_local_size(0);
  int v = g < nbins ? counts[g] : 0;
  tmp[l] = v;
  scan_local(tmp, l, w);
  if (g < nbins) starts[g] = tmp[l] - v;
  if (l == w - 1) sums[get_group_id(0)] = tmp[l];
}

/* Step 2: one work-group scans the block sums in chunks, carrying the running total. */
__kernel void scan_sums(__global const int* gate, __global int* sums, int nblocks, __local int* tmp) {
  if (!gate[0]) return;
  int l = get_local_id(0), w = get_local_size(0);
  int carry = 0;
  for (int base = 0; base < nblocks; base += w) {
    int v = base + l < nblocks ? sums[base + l] : 0;
    tmp[l] = v;
    scan_local(tmp, l, w);
    if (base + l < nblocks) sums[base + l] = carry + tmp[l] - v;
    carry += tmp[w - 1];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}

/* Step 3: add the block offsets; the scatter cursor starts at each bin's start; starts[nbins] = the total. */
__kernel void scan_add(__global const int* gate, __global int* starts, __global const int* sums,
                       __global const int* counts, int nbins, __global int* cursor) {
  if (!gate[0]) return;
  int g = get_global_id(0);
  if (g < nbins) {
    int s = starts[g] + sums[get_group_id(0)];
    starts[g] = s;
    cursor[g] = s;
    if (g == nbins - 1) starts[nbins] = s + counts[g];
  }
}

/* Elements [first, first + n) into bin order (order within a bin is arbitrary: force sums are order-independent);
   sorted_index holds the element index (first + k). */
__kernel void scatter(__global const real4* pos, int first, __global const int* bin, __global int* cursor,
                      __global real4* sorted_pos, __global int* sorted_index, int n) {
  int i = get_global_id(0);
  if (i >= n) return;
  int s = atomic_inc(&cursor[bin[i]]);
  sorted_pos[s] = pos[first + i];
  sorted_index[s] = first + i;
}

/* Candidates taken at a time by the binned pair kernels: the bits of one mask. */
#define SEMLB_CHUNK 64

/* The forces on element i (at me, in bin b, key keys[i]) of the sorted elements in the 27-bin stencil: 9 rows of
   3 bins, contiguous in bin order (starts[bin] the first sorted slot of a bin). Sorted slot `self` (i itself,
   or -1) is skipped. A row's candidates are taken SEMLB_CHUNK at a time: first a bit mask of those within the
   cutoff (a NaN distance counts as within, as in semlb_pair_force), then the force law on the set bits only, so
   that the lanes of a warp run the costly part together rather than idling through it for every candidate that
   one lane alone keeps (docs/engine.md: 1.13x float, 1.31x double on an H200 at 6.5e6 elements). */
static inline void stencil_forces(real4 me, int i, int self, int4 b, int4 dims, __global const real4* sorted_pos,
                                  __global const int* sorted_index, __global const int* starts,
                                  __global const ulong* keys, __constant const SEMLB_REAL* table,
                                  SEMLB_REAL cutoff2, long* acc) {
  int info = INFO(me.w);
  int x0 = max(b.x - 1, 0), x1 = min(b.x + 1, dims.x - 1);
  for (int z = max(b.z - 1, 0); z <= min(b.z + 1, dims.z - 1); ++z)
    for (int y = max(b.y - 1, 0); y <= min(b.y + 1, dims.y - 1); ++y) {
      int row = (z * dims.y + y) * dims.x;
      int last = starts[row + x1 + 1];
      for (int base = starts[row + x0]; base < last; base += SEMLB_CHUNK) {
        int m = min(SEMLB_CHUNK, last - base);
        ulong mask = 0;
        for (int k = 0; k < m; ++k) {
          real4 q = sorted_pos[base + k];
          SEMLB_REAL dx = me.x - q.x, dy = me.y - q.y, dz = me.z - q.z;
          if (!(dx * dx + dy * dy + dz * dz >= cutoff2)) mask |= (ulong)1 << k;
        }
        if (self >= base && self < base + m) mask &= ~((ulong)1 << (self - base));
        while (mask) {
          int k = 63 - (int)clz(mask & (0 - mask));  /* the lowest set bit */
          mask &= mask - 1;
          real4 q = sorted_pos[base + k];
          if (semlb_pair_force(me.x - q.x, me.y - q.y, me.z - q.z, info, INFO(q.w), table, cutoff2, acc) < 0)
            semlb_coincident_force(keys[i], keys[sorted_index[base + k]], info, INFO(q.w), table, acc);
        }
      }
    }
}

/* Local pair forces (owned on owned): one item per sorted owned element, over the owned elements' bins. */
__kernel void forces_binned(__global const real4* sorted_pos, __global const int* sorted_index,
                            __global const ulong* keys, __global const int* starts, real4 lo, real4 size, int4 dims,
                            __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force, int n,
                            int owned) {
  int s = get_global_id(0);
  if (s >= n || sorted_index[s] >= owned) return;  /* ghosts exert forces but receive none */
  real4 me = sorted_pos[s];
  int i = sorted_index[s];
  long acc[3] = {0, 0, 0};
  stencil_forces(me, i, s, bin3(me, lo, size, dims), dims, sorted_pos, sorted_index, starts, keys, table,
                 cutoff * cutoff, acc);
  force[3 * i] += acc[0];
  force[3 * i + 1] += acc[1];
  force[3 * i + 2] += acc[2];
}

/* Non-local pair forces (ghosts on owned): one item per owned element near a slab boundary, near[k] its index
   (-1: none; the band selection's list), or item k = element k when all != 0; each visits the 27-bin stencil in
   the ghosts' own bins (ghost_pos, ghost_index, ghost_starts: the bin sort of the ghosts alone). */
__kernel void forces_nonlocal(__global const real4* pos, __global const ulong* keys, __global const int* near,
                              int items, int all, __global const real4* ghost_pos, __global const int* ghost_index,
                              __global const int* ghost_starts, real4 lo, real4 size, int4 dims,
                              __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force) {
  int k = get_global_id(0);
  if (k >= items) return;
  int i = all ? k : near[k];
  if (i < 0) return;
  real4 me = pos[i];
  long acc[3] = {0, 0, 0};
  stencil_forces(me, i, -1, bin3(me, lo, size, dims), dims, ghost_pos, ghost_index, ghost_starts, keys, table,
                 cutoff * cutoff, acc);
  force[3 * i] += acc[0];
  force[3 * i + 1] += acc[1];
  force[3 * i + 2] += acc[2];
}

/* All pairs, tiled through local memory (the GPU all-pairs baseline of the paper): the forces of elements
   [from, n) on owned elements. Local part: from 0, n = owned, item k = element k (all != 0). Non-local part:
   from = owned (the ghosts), item k = element near[k] (-1: none) for k < items, as forces_nonlocal. */
__kernel void forces_allpairs(__global const real4* pos, __global const ulong* keys, __constant const SEMLB_REAL* table,
                              SEMLB_REAL cutoff2, __global long* force, int n, int from, __local real4* tile,
                              __global const int* near, int items, int all) {
  int k = get_global_id(0), l = get_local_id(0), w = get_local_size(0);
  int i = k < items ? (all ? k : near[k]) : -1;
  real4 me = i >= 0 ? pos[i] : (real4)(0);
  int info = INFO(me.w);
  long acc[3] = {0, 0, 0};
  for (int base = from; base < n; base += w) {
    tile[l] = base + l < n ? pos[base + l] : (real4)(0);
    barrier(CLK_LOCAL_MEM_FENCE);
    int count = min(w, n - base);
    if (i >= 0)
      for (int t = 0; t < count; ++t) {
        int j = base + t;
        if (j == i) continue;
        real4 q = tile[t];
        if (semlb_pair_force(me.x - q.x, me.y - q.y, me.z - q.z, info, INFO(q.w), table, cutoff2, acc) < 0)
          semlb_coincident_force(keys[i], keys[j], info, INFO(q.w), table, acc);
      }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (i < 0) return;
  force[3 * i] += acc[0];
  force[3 * i + 1] += acc[1];
  force[3 * i + 2] += acc[2];
}

#include "neighbour_list.cl"

/* The element terms (terms/NAME.h), each followed by its kernel from terms/element_term.cl. */
#include "element_terms.cl"

/* Overdamped update; the first failing step records (step, lowest element*4+code) and completes on every
   element; later steps (fail[0] < step) move nothing, so the frozen state does not depend on launch order. */
__kernel void integrate(__global real4* pos, __global const long* force, SEMLB_REAL dt_over_eta, SEMLB_REAL limit2,
                        int step, __global volatile int* fail, int n) {
  int i = get_global_id(0);
  if (i >= n || (fail[0] >= 0 && fail[0] < step)) return;
  real4 p = pos[i];
  SEMLB_REAL dx = semlb_displacement(force[3 * i], dt_over_eta);
  SEMLB_REAL dy = semlb_displacement(force[3 * i + 1], dt_over_eta);
  SEMLB_REAL dz = semlb_displacement(force[3 * i + 2], dt_over_eta);
  p.x += dx;
  p.y += dy;
  p.z += dz;
  int finite = isfinite(p.x) && isfinite(p.y) && isfinite(p.z);
  if (!finite || !(dx * dx + dy * dy + dz * dz <= limit2)) {
    atomic_min(&fail[1], i * 4 + (finite ? 2 : 1));
    atomic_xchg(&fail[0], step);
  }
  pos[i] = p;
}

/* Frozen, like integrate, after a failing step. */
__kernel void noise(__global real4* pos, __global const ulong* keys, SEMLB_REAL amplitude, ulong seed, long step,
                    __global const volatile int* fail, int n) {
  int i = get_global_id(0);
  if (i >= n || (fail[0] >= 0 && fail[0] < step)) return;
  real4 p = pos[i];
  ulong k = keys[i];
  p.x += amplitude * semlb_gauss(seed, k, (ulong)step, 0);
  p.y += amplitude * semlb_gauss(seed, k, (ulong)step, 1);
  p.z += amplitude * semlb_gauss(seed, k, (ulong)step, 2);
  pos[i] = p;
}

/* The x range of pos[0..n): each group reduces a strided share into out[2 group], out[2 group + 1]. */
__kernel void x_extent(__global const real4* pos, int n, __global SEMLB_REAL* out, __local SEMLB_REAL* lo,
                       __local SEMLB_REAL* hi) {
  int l = get_local_id(0);
  SEMLB_REAL a = (SEMLB_REAL)INFINITY, b = -(SEMLB_REAL)INFINITY;
  for (int i = get_global_id(0); i < n; i += get_global_size(0)) {
    a = fmin(a, pos[i].x);
    b = fmax(b, pos[i].x);
  }
  lo[l] = a;
  hi[l] = b;
  for (int off = get_local_size(0) / 2; off > 0; off >>= 1) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (l < off) {
      lo[l] = fmin(lo[l], lo[l + off]);
      hi[l] = fmax(hi[l], hi[l + off]);
    }
  }
  if (l == 0) {
    out[2 * get_group_id(0)] = lo[0];
    out[2 * get_group_id(0) + 1] = hi[0];
  }
}

/* Ghost bands: flag the elements beyond x, scan the flags, gather the flagged ones in element order. */
/* The two ghost bands in one pass over the owned elements: flags[i] = x < below (the band sent to the rank below),
   flags[n + i] = x > above (the band sent to the rank above); one exclusive scan over the 2n flags numbers both. */
__kernel void band_flags(__global const real4* pos, int n, SEMLB_REAL below, SEMLB_REAL above, __global int* flags) {
  int i = get_global_id(0);
  if (i >= n) return;
  SEMLB_REAL x = pos[i].x;
  flags[i] = x < below;
  flags[n + i] = x > above;
}

/* The bands compacted in element order, the lower one first (slots starts[i], then starts[n + i]); near[slot] the
   element index for the non-local forces, -1 in the upper band for an element the lower one already lists. */
__kernel void band_gather(__global const real4* pos, __global const ulong* keys, __global const int* flags,
                          __global const int* starts, int n, __global real4* out_pos, __global ulong* out_keys,
                          __global int* near) {
  int i = get_global_id(0);
  if (i >= n) return;
  for (int side = 0; side < 2; ++side)
    if (flags[side * n + i]) {
      int s = starts[side * n + i];
      out_pos[s] = pos[i];
      out_keys[s] = keys[i];
      near[s] = side == 1 && flags[i] ? -1 : i;
    }
}

/* ---- Cell stage (growth, division, differentiation) on the device; rules from cells.h. ---------------- */
/* The bounding box of the finite coordinates of pos[0..n): per group lo.xyz, hi.xyz into out[6 group ..]. */
__kernel void bounds(__global const real4* pos, int n, __global SEMLB_REAL* out, __local SEMLB_REAL* lo,
                     __local SEMLB_REAL* hi) {
  int l = get_local_id(0), w = get_local_size(0);
  for (int d = 0; d < 3; ++d) {
    SEMLB_REAL a = (SEMLB_REAL)INFINITY, b = -(SEMLB_REAL)INFINITY;
    for (int i = get_global_id(0); i < n; i += get_global_size(0)) {
      SEMLB_REAL x = ((__global const SEMLB_REAL*)pos)[4 * i + d];
      if (isfinite(x)) {
        a = fmin(a, x);
        b = fmax(b, x);
      }
    }
    lo[l] = a;
    hi[l] = b;
    for (int off = w / 2; off > 0; off >>= 1) {
      barrier(CLK_LOCAL_MEM_FENCE);
      if (l < off) {
        lo[l] = fmin(lo[l], lo[l + off]);
        hi[l] = fmax(hi[l], hi[l + off]);
      }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (l == 0) {
      out[6 * get_group_id(0) + d] = lo[0];
      out[6 * get_group_id(0) + 3 + d] = hi[0];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}

#ifdef SEMLB_CELLS /* built when the device has fp64: the cell bookkeeping is double on every backend */
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF
#ifdef SEMLB_DOUBLE
#define CELL_INFO(i) as_double((long)(i))
#else
#define CELL_INFO(i) as_float(i)
#endif
#define SEMLB_CELL_IN __global const real4*
#define SEMLB_CELL_X(in, e, d) ((double)((__global const SEMLB_REAL*)(in))[4 * (e) + (d)])
#define SEMLB_CELL_OUT __global real4*
#define SEMLB_CELL_KEYS __global ulong*
#define SEMLB_CELL_PUT(out, keys, e, x, y, z, info, key) \
  ((out)[e] = (real4)((SEMLB_REAL)(x), (SEMLB_REAL)(y), (SEMLB_REAL)(z), CELL_INFO(info)), (keys)[e] = (key))
#include "cells.h"

/* Per cell: growth (clock, births), the division decision and its split plan. counts[c] = the cell's
   elements after the stage, counts[n + c] = its daughter's (0 if none); divides[c] = 0 or 1; a cell that
   would divide past the id depth records its index in fail[0] (atomic_min). */
__kernel void cells_plan(int n, semlb_cell_rules r, ulong seed, ulong step, double elapsed, __global const real4* pos,
                         __global const ulong* id, __global const int* type, __global const int* first,
                         __global const int* count, __global double* clock, __global const double* depth,
                         __global int* births, __global double* old_centroid, __global semlb_cell_split* split,
                         __global int* counts, __global int* divides, __global volatile int* fail) {
  int c = get_global_id(0);
  if (c >= n) return;
  double clk = clock[c], ctr[3];
  int t = type[c], cnt = count[c];
  semlb_cell_centroid(pos, first[c], cnt, ctr);
  int b = semlb_cell_births(&r, t, cnt, ctr[0], elapsed, &clk);
  clock[c] = clk;
  births[c] = b;
  for (int d = 0; d < 3; ++d) old_centroid[3 * c + d] = ctr[d];
  int grown = cnt + b;
  int div = r.division && ((r.division_types >> t) & 1) && grown >= r.at_elements;
  if (div && (int)depth[c] >= SEMLB_CELL_MAX_DEPTH) {
    atomic_min(&fail[0], c);
    div = 0;
  }
  int leave = 0;
  if (div) {
    semlb_cell_split s;
    semlb_cell_plan_split(pos, first[c], cnt, b, ctr, &r, seed, id[c], step, &s);
    split[c] = s;
    leave = s.leave;
  }
  divides[c] = div;
  counts[c] = grown - leave;
  counts[n + c] = leave;
}

/* Per cell: writes the mother (index c) and its daughter (index n + dstarts[c]) into the new arrays:
   elements at estarts[c] / estarts[n + c] (exclusive scans of counts and divides). */
__kernel void cells_rewrite(int n, semlb_cell_rules r, ulong seed, ulong step, __global const real4* pos,
                            __global const ulong* id, __global const int* type, __global const int* first,
                            __global const int* count, __global const double* clock, __global const double* depth,
                            __global const double* age, __global const int* births, __global const double* old_centroid,
                            __global const semlb_cell_split* split, __global const int* counts,
                            __global const int* divides, __global const int* estarts, __global const int* dstarts,
                            __global real4* out_pos, __global ulong* out_keys, __global ulong* out_id,
                            __global int* out_type, __global int* out_first, __global int* out_count,
                            __global double* out_clock, __global double* out_depth, __global double* out_age) {
  int c = get_global_id(0);
  if (c >= n) return;
  int div = divides[c], t = type[c];
  double dep = depth[c] + div, ctr[3] = {old_centroid[3 * c], old_centroid[3 * c + 1], old_centroid[3 * c + 2]};
  ulong me = id[c], daughter = div ? me | ((ulong)1 << (SEMLB_CELL_ROOT_ID_BITS + (int)depth[c])) : 0;
  int dc = n + dstarts[c];
  out_id[c] = me;
  out_type[c] = t;
  out_first[c] = estarts[c];
  out_count[c] = counts[c];
  out_clock[c] = clock[c];
  out_depth[c] = dep;
  out_age[c] = age[c];
  semlb_cell_split s;
  if (div) {
    s = split[c];
    out_id[dc] = daughter;
    out_type[dc] = t;
    out_first[dc] = estarts[n + c];
    out_count[dc] = counts[n + c];
    out_clock[dc] = clock[c];
    out_depth[dc] = dep;
    out_age[dc] = age[c];
  }
  semlb_cell_rewrite(pos, first[c], count[c], births[c], ctr, &r, seed, step, me, t, estarts[c], c, div ? &s : 0,
                     daughter, estarts[n + c], dc, out_pos, out_keys);
}

/* Per cell of the new state: differentiation on its own centroid; a new type is written into its elements. */
__kernel void cells_differentiate(int n, semlb_cell_rules r, double elapsed, __global real4* pos,
                                  __global const int* first, __global const int* count, __global int* type,
                                  __global double* age) {
  int c = get_global_id(0);
  if (c >= n) return;
  double ctr[3], a = age[c];
  int t = type[c];
  semlb_cell_centroid(pos, first[c], count[c], ctr);
  int changed = semlb_cell_differentiate(&r, ctr[2], elapsed, &t, &a);
  age[c] = a;
  if (!changed) return;
  type[c] = t;
  for (int k = 0; k < count[c]; ++k) pos[first[c] + k].w = CELL_INFO(semlb_info_pack(c, t));
}

/* ---- The decomposition on the device: W_s (a reduction) and migration (owners, packing, compaction). ---- */
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
/* Grid::bin_of and SliceMap::slice_of (backend.cpp) in double: floor, clamped, NaN -> 0. */
static inline int clamp_floor(double f, int n) { return !(f >= 0) ? 0 : (f >= n ? n - 1 : (int)f); }
static inline long work_bin(__global const real4* pos, int e, double4 lo, double4 size, int4 dims, int4* b) {
  (*b).x = clamp_floor(floor((SEMLB_CELL_X(pos, e, 0) - lo.x) / size.x), dims.x);
  (*b).y = clamp_floor(floor((SEMLB_CELL_X(pos, e, 1) - lo.y) / size.y), dims.y);
  (*b).z = clamp_floor(floor((SEMLB_CELL_X(pos, e, 2) - lo.z) / size.z), dims.z);
  return ((long)(*b).z * dims.y + (*b).y) * dims.x + (*b).x;
}

/* Elements per bin over pos[0..n) (the owned elements; other ranks' are summed in by the host); counts zeroed before. */
__kernel void work_bins(__global const real4* pos, int n, double4 lo, double4 size, int4 dims, __global int* counts) {
  int i = get_global_id(0);
  int4 b;
  if (i < n) atomic_inc(&counts[work_bin(pos, i, lo, size, dims, &b)]);
}

/* Per cell: w_i = n_i * (elements in the 3x3x3 bins around its centroid's bin), added to its slice (exact). */
__kernel void work_cells(int n, __global const real4* pos, __global const int* first, __global const int* count,
                         double4 lo, double4 size, int4 dims, __global const int* counts, double x0, double width,
                         int slices, __global long* work) {
  int c = get_global_id(0);
  if (c >= n) return;
  double ctr[3];
  semlb_cell_centroid(pos, first[c], count[c], ctr);
  int4 b;
  b.x = clamp_floor(floor((ctr[0] - lo.x) / size.x), dims.x);
  b.y = clamp_floor(floor((ctr[1] - lo.y) / size.y), dims.y);
  b.z = clamp_floor(floor((ctr[2] - lo.z) / size.z), dims.z);
  long near = 0;
  for (int z = max(b.z - 1, 0); z <= min(b.z + 1, dims.z - 1); ++z)
    for (int y = max(b.y - 1, 0); y <= min(b.y + 1, dims.y - 1); ++y)
      for (int x = max(b.x - 1, 0); x <= min(b.x + 1, dims.x - 1); ++x) near += counts[((long)z * dims.y + y) * dims.x + x];
  atom_add(&work[clamp_floor(floor((ctr[0] - x0) / width), slices)], (long)count[c] * near);
}

/* Per cell: its owner (owner_of: interior boundaries at or below its centroid's slice), leave[c] = owner != rank,
   and its elements counted among the leavers' (elems[c]) or the stayers' (elems[n + c]). */
__kernel void cells_owner(int n, __global const real4* pos, __global const int* first, __global const int* count,
                          double x0, double width, int slices, __global const int* bounds, int nb, int rank,
                          __global int* leave, __global int* owner, __global int* elems) {
  int c = get_global_id(0);
  if (c >= n) return;
  double ctr[3];
  semlb_cell_centroid(pos, first[c], count[c], ctr);
  int s = clamp_floor(floor((ctr[0] - x0) / width), slices), o = 0;
  for (int k = 0; k < nb; ++k) o += bounds[k] <= s;
  int l = o != rank;
  owner[c] = o;
  leave[c] = l;
  elems[c] = l ? count[c] : 0;
  elems[n + c] = l ? 0 : count[c];
}

/* Per cell: a leaver goes to slot lstarts[c] of the l_ arrays (l_first holds its new owner), its elements at
   estarts[c]; a stayer to slot c - lstarts[c] of the out_ arrays, its elements at estarts[n + c] - estarts[n],
   their info renumbered to the new cell index. */
__kernel void cells_split(int n, __global const real4* pos, __global const ulong* keys, __global const ulong* id,
                          __global const int* type, __global const int* first, __global const int* count,
                          __global const double* clock, __global const double* depth, __global const double* age,
                          __global const int* leave, __global const int* owner, __global const int* lstarts,
                          __global const int* estarts, __global real4* out_pos, __global ulong* out_keys,
                          __global ulong* out_id, __global int* out_type, __global int* out_first,
                          __global int* out_count, __global double* out_clock, __global double* out_depth,
                          __global double* out_age, __global real4* l_pos, __global ulong* l_id, __global int* l_type,
                          __global int* l_first, __global int* l_count, __global double* l_clock,
                          __global double* l_depth, __global double* l_age) {
  int c = get_global_id(0);
  if (c >= n) return;
  int f = first[c], m = count[c], t = type[c];
  if (leave[c]) {
    int j = lstarts[c], at = estarts[c];
    l_id[j] = id[c];
    l_type[j] = t;
    l_first[j] = owner[c];
    l_count[j] = m;
    l_clock[j] = clock[c];
    l_depth[j] = depth[c];
    l_age[j] = age[c];
    for (int k = 0; k < m; ++k) l_pos[at + k] = pos[f + k];
    return;
  }
  int j = c - lstarts[c], at = estarts[n + c] - estarts[n];
  out_id[j] = id[c];
  out_type[j] = t;
  out_first[j] = at;
  out_count[j] = m;
  out_clock[j] = clock[c];
  out_depth[j] = depth[c];
  out_age[j] = age[c];
  for (int k = 0; k < m; ++k) {
    real4 p = pos[f + k];
    p.w = CELL_INFO(semlb_info_pack(j, t));
    out_pos[at + k] = p;
    out_keys[at + k] = keys[f + k];
  }
}
#endif
