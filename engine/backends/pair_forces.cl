/* Pair forces over the 27-bin stencil (local and non-local parts) and over all pairs (kernels.cl includes
   it). */
/* Candidates taken at a time by the binned pair kernels: the bits of one mask. */
#define SEMLB_CHUNK 64

/* The forces on element i (at me, in bin b, key keys[i]) of the sorted elements in the stencil of `reach` bins
   each way (1: the 27-bin stencil of bins of edge >= the cutoff, 9 rows of 3 bins), rows contiguous in bin order
   (starts[bin] the first sorted slot of a bin). Sorted slot `self` (i itself, or -1) is skipped. A row's candidates are
   taken SEMLB_CHUNK at a time: first a bit mask of those within the cutoff (a NaN distance counts as within, as in
   semlb_pair_force), then the force law on the set bits only, so that the lanes of a warp run the costly part together
   rather than idling through it for every candidate that one lane alone keeps (docs/engine.md: 1.13x float, 1.31x
   double on an H200 at 6.5e6 elements). */
static inline void stencil_forces(real4 me, int i, int self, int4 b, int4 dims, int reach,
                                  __global const real4* sorted_pos, __global const int* sorted_index,
                                  __global const int* starts, __global const ulong* keys,
                                  __constant const SEMLB_REAL* table, SEMLB_REAL cutoff2, long* acc) {
  int info = INFO(me.w);
  SEMLB_STENCIL_ROWS_REACH(b.x, b.y, b.z, dims.x, dims.y, dims.z, reach, first_bin, last_bin) {
    int last = starts[last_bin + 1];
    for (int base = starts[first_bin]; base < last; base += SEMLB_CHUNK) {
      int m = min(SEMLB_CHUNK, last - base);
      ulong mask = 0;
      for (int k = 0; k < m; ++k) {
        real4 q = sorted_pos[base + k];
        SEMLB_REAL dx = me.x - q.x, dy = me.y - q.y, dz = me.z - q.z;
        if (!(dx * dx + dy * dy + dz * dz >= cutoff2)) mask |= (ulong)1 << k;
      }
      if (self >= base && self < base + m) mask &= ~((ulong)1 << (self - base));
      while (mask) {
        int k = 63 - (int)clz(mask & (0 - mask)); /* the lowest set bit */
        mask &= mask - 1;
        real4 q = sorted_pos[base + k];
        if (semlb_pair_force(me.x - q.x, me.y - q.y, me.z - q.z, info, INFO(q.w), table, cutoff2, acc) < 0)
          semlb_coincident_force(keys[i], keys[sorted_index[base + k]], info, INFO(q.w), table, acc);
      }
    }
  }
}

/* Local pair forces (owned on owned) on sorted slot s, over the owned elements' bins. */
static inline void binned_slot_forces(int s, __global const real4* sorted_pos, __global const int* sorted_index,
                                      __global const ulong* keys, __global const int* starts, real4 lo, real4 size,
                                      int4 dims, __constant const SEMLB_REAL* table, SEMLB_REAL cutoff,
                                      __global long* force, __global long* bound, int owned) {
  if (sorted_index[s] >= owned) return; /* ghosts exert forces but receive none */
  real4 me = sorted_pos[s];
  int i = sorted_index[s];
  long acc[4] = {0, 0, 0, 0};
  stencil_forces(me, i, s, bin3(me, lo, size, dims), dims, 1, sorted_pos, sorted_index, starts, keys, table,
                 cutoff * cutoff, acc);
  force[3 * i] += acc[0];
  force[3 * i + 1] += acc[1];
  force[3 * i + 2] += acc[2];
  bound[i] += acc[3];
}

/* Local pair forces: one item per sorted owned element. */
__kernel void forces_binned(__global const real4* sorted_pos, __global const int* sorted_index,
                            __global const ulong* keys, __global const int* starts, real4 lo, real4 size, int4 dims,
                            __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force,
                            __global long* bound, int n, int owned) {
  int s = get_global_id(0);
  if (s >= n) return;
  binned_slot_forces(s, sorted_pos, sorted_index, keys, starts, lo, size, dims, table, cutoff, force, bound, owned);
}

/* The same for the sorted slots items[first .. first + n) alone (the measured cost of a region of the tissue,
   docs/measured_time.md; `force` and `bound` are scratch buffers there). */
__kernel void forces_binned_items(__global const real4* sorted_pos, __global const int* sorted_index,
                                  __global const ulong* keys, __global const int* starts, real4 lo, real4 size,
                                  int4 dims, __constant const SEMLB_REAL* table, SEMLB_REAL cutoff,
                                  __global long* force, __global long* bound, int owned, __global const int* items,
                                  int first, int n) {
  int k = get_global_id(0);
  if (k >= n) return;
  binned_slot_forces(items[first + k], sorted_pos, sorted_index, keys, starts, lo, size, dims, table, cutoff, force,
                     bound, owned);
}

/* Non-local pair forces (ghosts on owned): one item per owned element near a slab boundary, near[k] its index
   (-1: none; the band selection's list), or item k = element k when all != 0; each visits the 27-bin stencil in
   the ghosts' own bins (ghost_pos, ghost_index, ghost_starts: the bin sort of the ghosts alone). */
__kernel void forces_nonlocal(__global const real4* pos, __global const ulong* keys, __global const int* near,
                              int items, int all, __global const real4* ghost_pos, __global const int* ghost_index,
                              __global const int* ghost_starts, real4 lo, real4 size, int4 dims,
                              __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force,
                              __global long* bound) {
  int k = get_global_id(0);
  if (k >= items) return;
  int i = all ? k : near[k];
  if (i < 0) return;
  real4 me = pos[i];
  long acc[4] = {0, 0, 0, 0};
  stencil_forces(me, i, -1, bin3(me, lo, size, dims), dims, 1, ghost_pos, ghost_index, ghost_starts, keys, table,
                 cutoff * cutoff, acc);
  force[3 * i] += acc[0];
  force[3 * i + 1] += acc[1];
  force[3 * i + 2] += acc[2];
  bound[i] += acc[3];
}

/* All pairs, tiled through local memory (the GPU all-pairs baseline of the paper): the forces of elements
   [from, n) on owned elements. Local part: from 0, n = owned, item k = element k (all != 0). Non-local part:
   from = owned (the ghosts), item k = element near[k] (-1: none) for k < items, as forces_nonlocal. */
__kernel void forces_allpairs(__global const real4* pos, __global const ulong* keys, __constant const SEMLB_REAL* table,
                              SEMLB_REAL cutoff2, __global long* force, __global long* bound, int n, int from,
                              __local real4* tile, __global const int* near, int items, int all) {
  int k = get_global_id(0), l = get_local_id(0), w = get_local_size(0);
  int i = k < items ? (all ? k : near[k]) : -1;
  real4 me = i >= 0 ? pos[i] : (real4)(0);
  int info = INFO(me.w);
  long acc[4] = {0, 0, 0, 0};
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
  bound[i] += acc[3];
}
