/* The cell stage on the device: the core of cells.h around the scene's growth law (engine/growth) and division rule
   (engine/division), then fate rules (engine/fates); W_s, owners and the migration split (kernels.cl includes it). */
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
/* Every growth law (growth/NAME.h) and the dispatch semlb_growth_law(law, ...) over them in name order, from
   growth/growth_law.cl; every division rule (division/NAME.h) and the dispatches semlb_divides(rule, ...) and
   semlb_division_axis(rule, ...), from division/division_rule.cl. */
#include "growth_laws.cl"
#include "division_rules.cl"

/* Cell c's field record: r.fields doubles (cells.h), cell-major. Field k (-1: absent) of a record, 0 when absent. */
#define CELL_RECORD(fields, nf, c) ((fields) + (long)(c) * (nf))
static inline double cell_field(__global const double* rec, int k) { return k >= 0 ? rec[k] : 0.0; }
static inline void copy_record(__global const double* from, __global double* to, int nf) {
  for (int k = 0; k < nf; ++k) to[k] = from[k];
}

/* Per cell: growth (the law's field, births), the division decision and its split plan. counts[c] = the cell's
   elements after the stage, counts[n + c] = its daughter's (0 if none); divides[c] = 0 or 1. A cell that would divide
   past the id depth records its index in fail[0], one whose law returns births < 0 or beyond kMaxSlots - 1 elements
   in fail[1] (atomic_min). */
__kernel void cells_plan(int n, semlb_cell_rules r, ulong seed, ulong step, double elapsed, __global const real4* pos,
                         __global const ulong* id, __global const int* type, __global const int* first,
                         __global const int* count, __global double* fields, __global int* births,
                         __global double* old_centroid, __global semlb_cell_split* split, __global int* counts,
                         __global int* divides, __global volatile int* fail) {
  int c = get_global_id(0);
  if (c >= n) return;
  __global double* rec = CELL_RECORD(fields, r.fields, c);
  double clk = cell_field(rec, r.growth_field), ctr[3];
  int t = type[c], cnt = count[c];
  semlb_cell_centroid(pos, first[c], cnt, ctr);
  int b = r.growth >= 0 ? semlb_growth_law(r.growth, t, cnt, ctr, r.time, elapsed, r.growth_p, &clk) : 0;
  if (b < 0 || cnt + b > SEMLB_CELL_MAX_ELEMENTS) {
    atomic_min(&fail[1], c);
    b = 0;
  }
  if (r.growth_field >= 0) rec[r.growth_field] = clk;
  births[c] = b;
  for (int d = 0; d < 3; ++d) old_centroid[3 * c + d] = ctr[d];
  int grown = cnt + b;
  int div = r.division >= 0 && semlb_divides(r.division, t, grown, ctr, r.division_p);
  if (div && (int)cell_field(rec, r.depth_field) >= SEMLB_CELL_MAX_DEPTH) {
    atomic_min(&fail[0], c);
    div = 0;
  }
  int leave = 0;
  if (div) {
    semlb_cell_split s;
    double g[6];
    semlb_cell_gyration(pos, first[c], cnt, b, ctr, &r, seed, id[c], step, &s, g);
    semlb_division_axis(r.division, g, s.centroid, r.division_p, s.axis);
    semlb_cell_plan_halves(pos, first[c], cnt, ctr, &r, seed, id[c], step, &s);
    split[c] = s;
    leave = s.leave;
  }
  divides[c] = div;
  counts[c] = grown - leave;
  counts[n + c] = leave;
}

/* Per cell: writes the mother (index c) and its daughter (index n + dstarts[c]) into the new arrays:
   elements at estarts[c] / estarts[n + c] (exclusive scans of counts and divides); the daughter inherits the
   mother's field record, and both count the division in the depth field. */
__kernel void cells_rewrite(int n, semlb_cell_rules r, ulong seed, ulong step, __global const real4* pos,
                            __global const ulong* id, __global const int* type, __global const int* first,
                            __global const int* count, __global const double* fields, __global const int* births,
                            __global const double* old_centroid, __global const semlb_cell_split* split,
                            __global const int* counts, __global const int* divides, __global const int* estarts,
                            __global const int* dstarts, __global real4* out_pos, __global ulong* out_keys,
                            __global ulong* out_id, __global int* out_type, __global int* out_first,
                            __global int* out_count, __global double* out_fields) {
  int c = get_global_id(0);
  if (c >= n) return;
  int div = divides[c], t = type[c], nf = r.fields;
  __global const double* rec = CELL_RECORD(fields, nf, c);
  double depth = cell_field(rec, r.depth_field), dep = depth + div;
  double ctr[3] = {old_centroid[3 * c], old_centroid[3 * c + 1], old_centroid[3 * c + 2]};
  ulong me = id[c], daughter = div ? me | ((ulong)1 << (SEMLB_CELL_ROOT_ID_BITS + (int)depth)) : 0;
  int dc = n + dstarts[c];
  out_id[c] = me;
  out_type[c] = t;
  out_first[c] = estarts[c];
  out_count[c] = counts[c];
  copy_record(rec, CELL_RECORD(out_fields, nf, c), nf);
  if (r.depth_field >= 0) CELL_RECORD(out_fields, nf, c)[r.depth_field] = dep;
  semlb_cell_split s;
  if (div) {
    s = split[c];
    out_id[dc] = daughter;
    out_type[dc] = t;
    out_first[dc] = estarts[n + c];
    out_count[dc] = counts[n + c];
    copy_record(rec, CELL_RECORD(out_fields, nf, dc), nf);
    if (r.depth_field >= 0) CELL_RECORD(out_fields, nf, dc)[r.depth_field] = dep;
  }
  semlb_cell_rewrite(pos, first[c], count[c], births[c], ctr, &r, seed, step, me, t, estarts[c], c, div ? &s : 0,
                     daughter, estarts[n + c], dc, out_pos, out_keys);
}

/* ---- The decomposition on the device: W_s (a reduction) and migration (owners, packing, compaction). ---- */
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
/* Grid::bin_of, SliceMap::slice_of, owner_of and the 27-bin count of W_s (model/slices.hpp) in double. */
#define SEMLB_FLOOR floor
#define SEMLB_GLOBAL __global
#include "slices.h"
static inline long work_bin(__global const real4* pos, int e, double4 lo, double4 size, int4 dims, int4* b) {
  (*b).x = semlb_bin_of(SEMLB_CELL_X(pos, e, 0), lo.x, size.x, dims.x);
  (*b).y = semlb_bin_of(SEMLB_CELL_X(pos, e, 1), lo.y, size.y, dims.y);
  (*b).z = semlb_bin_of(SEMLB_CELL_X(pos, e, 2), lo.z, size.z, dims.z);
  return ((long)(*b).z * dims.y + (*b).y) * dims.x + (*b).x;
}

/* Elements per bin over pos[0..n) (the owned elements; other ranks' are summed in by the host); counts zeroed before.
 */
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
  long near =
      semlb_near_count(counts, semlb_bin_of(ctr[0], lo.x, size.x, dims.x), semlb_bin_of(ctr[1], lo.y, size.y, dims.y),
                       semlb_bin_of(ctr[2], lo.z, size.z, dims.z), dims.x, dims.y, dims.z);
  atom_add(&work[semlb_slice_of(ctr[0], x0, width, slices)], (long)count[c] * near);
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
  int o = semlb_owner_of(semlb_slice_of(ctr[0], x0, width, slices), bounds, nb);
  int l = o != rank;
  owner[c] = o;
  leave[c] = l;
  elems[c] = l ? count[c] : 0;
  elems[n + c] = l ? 0 : count[c];
}

/* Per cell: a leaver goes to slot lstarts[c] of the l_ arrays (l_first holds its new owner), its elements at
   estarts[c]; a stayer to slot c - lstarts[c] of the out_ arrays, its elements at estarts[n + c] - estarts[n],
   their info renumbered to the new cell index. Each cell's field record (nf doubles) goes with it. */
__kernel void cells_split(int n, int nf, __global const real4* pos, __global const ulong* keys,
                          __global const ulong* id, __global const int* type, __global const int* first,
                          __global const int* count, __global const double* fields, __global const int* leave,
                          __global const int* owner, __global const int* lstarts, __global const int* estarts,
                          __global real4* out_pos, __global ulong* out_keys, __global ulong* out_id,
                          __global int* out_type, __global int* out_first, __global int* out_count,
                          __global double* out_fields, __global real4* l_pos, __global ulong* l_id,
                          __global int* l_type, __global int* l_first, __global int* l_count,
                          __global double* l_fields) {
  int c = get_global_id(0);
  if (c >= n) return;
  int f = first[c], m = count[c], t = type[c];
  if (leave[c]) {
    int j = lstarts[c], at = estarts[c];
    l_id[j] = id[c];
    l_type[j] = t;
    l_first[j] = owner[c];
    l_count[j] = m;
    copy_record(CELL_RECORD(fields, nf, c), CELL_RECORD(l_fields, nf, j), nf);
    for (int k = 0; k < m; ++k) l_pos[at + k] = pos[f + k];
    return;
  }
  int j = c - lstarts[c], at = estarts[n + c] - estarts[n];
  out_id[j] = id[c];
  out_type[j] = t;
  out_first[j] = at;
  out_count[j] = m;
  copy_record(CELL_RECORD(fields, nf, c), CELL_RECORD(out_fields, nf, j), nf);
  for (int k = 0; k < m; ++k) {
    real4 p = pos[f + k];
    p.w = CELL_INFO(semlb_info_pack(j, t));
    out_pos[at + k] = p;
    out_keys[at + k] = keys[f + k];
  }
}
/* The removal rules (removal/NAME.h), each followed by its flags kernel from removal/removal_rule.cl. */
#include "removal_rules.cl"
/* The fate rules (fates/NAME.h), each followed by its kernel from fates/fate_rule.cl. */
#include "fate_rules.cl"
#endif
