/* Per-element kernels: the overdamped update, noise, the x range and bounding box, the ghost bands (kernels.cl
   includes it). */
/* Overdamped update; the first failing step records (step, lowest element*4+code) and completes on every
   element; later steps (fail[0] < step) move nothing, so the frozen state does not depend on launch order. Code 3:
   the bound of the element's force sums (pair forces' bound[i] plus `terms`, pair_force.h) is above
   SEMLB_BOUND_LIMIT, so the sums may have wrapped; it is recorded as i - INT_MAX (< 0), so that it wins over
   every displacement a wrapped sum may have caused, the lowest such element first. */
__kernel void integrate(__global real4* pos, __global const long* force, __global const long* bound, long terms,
                        SEMLB_REAL dt_over_eta, SEMLB_REAL limit2, int step, __global volatile int* fail, int n) {
  int i = get_global_id(0);
  if (i >= n || (fail[0] >= 0 && fail[0] < step)) return;
  if (bound[i] + terms > SEMLB_BOUND_LIMIT) {
    atomic_min(&fail[1], i - INT_MAX);
    atomic_xchg(&fail[0], step);
  }
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
