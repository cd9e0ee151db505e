/* The neighbour list of opencl-binned (a Verlet list with a skin, reused across steps; docs/engine.md "Neighbour
   list"): pasted into kernels.cl after the pair kernels, whose helpers (bin3, stencil_forces) it uses.
   Per step: nl_check refreshes the sorted positions and raises gate[0] when an element has moved farther than the
   trigger since the last build; the build kernels (bins.cl's bin_count, scan and scatter, then nl_build, nl_done) run
   every step but return at once unless gate[0] is set, so the device decides when to rebuild and no count crosses
   to the host; nl_forces evaluates the listed pairs. The list: for sorted slot s, nl_count[s] partners (sorted
   slots, within cutoff + skin at the build) in chunks of 8 (32 bytes, one memory sector): chunk c of slot s at
   nl[NL_AT(s, c, kmax)] (column-major per warp of 32 slots: the 32 lanes' chunk c is 1 KB in a row, and a warp's
   whole list is one block of kmax x 128 bytes, so that its loads and the build's stores touch one page, and the
   build stores whole sectors (8 partners at a time from registers), not one word per partner); a slot with more than
   kmax partners keeps its count and takes the exact 27-bin stencil of the build's bins instead.
   -DSEMLB_NEWTON (opencl-binned's `newton: true`, LAMMPS's `newton on`): a half list, each pair once (partners j > s),
   its force added to both elements with 64-bit atomic adds; fixed-point sums do not depend on their order, so the
   forces are those of the full list bit for bit (pair_force.h semlb_pair_force_newton). */

#ifdef SEMLB_NEWTON
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#endif

/* Fraction of the skin an element may move before the list is rebuilt: half the skin less 2% for rounding (two
   elements that each moved less than this came closer by less than the skin). A build option so that the list
   test can show a wrong trigger being caught (-DSEMLB_NL_TRIGGER=3.0). */
#ifndef SEMLB_NL_TRIGGER
#define SEMLB_NL_TRIGGER 0.49
#endif

/* The list's bins: edge >= (cutoff + skin) / SEMLB_NL_REACH, each build and stencil fallback over the
   (2 SEMLB_NL_REACH + 1)^3 bins around a slot's (opencl-binned's `list_bin_divisions`, LAMMPS's `neigh_modify
   binsize`: smaller bins test fewer candidates at more rows each). */
#ifndef SEMLB_NL_REACH
#define SEMLB_NL_REACH 1
#endif

/* Where chunk c (partners 8c .. 8c + 7) of sorted slot s is stored: slot s is lane s % 32 of warp block s / 32;
   kmax is a multiple of 8. */
#define NL_WARP 32
#define NL_CHUNK 8
#define NL_AT(s, c, kmax) ((((long)((s) >> 5) * ((kmax) >> 3) + (c)) * NL_WARP + ((s) & (NL_WARP - 1))) * NL_CHUNK)

/* Sorted slot s of the last build: its position now (pos[sorted_index[s]]) into sorted_pos, and gate[0] = 1 when
   it moved by more than SEMLB_NL_TRIGGER skin since the build (ref[s]) or its displacement is not finite. With
   slices > 0 (a recording's list triggers, docs/measured_time.md) also moved[k] = 1 for the slice k of its x now:
   slice k covers [x0 + k / inv_width, x0 + (k + 1) / inv_width), clamped, NaN -> 0 (physics/slices.h semlb_slice_of,
   here in the kernel's precision: an element on a slice edge may land in either). */
__kernel void nl_check(__global const real4* pos, __global const int* sorted_index, __global const real4* ref,
                       __global real4* sorted_pos, int n, SEMLB_REAL skin, __global int* gate, __global int* moved,
                       SEMLB_REAL x0, SEMLB_REAL inv_width, int slices) {
  int s = get_global_id(0);
  if (s >= n) return;
  SEMLB_REAL t = (SEMLB_REAL)SEMLB_NL_TRIGGER * skin, trigger2 = t * t;
  real4 p = pos[sorted_index[s]], r = ref[s];
  sorted_pos[s] = p;
  SEMLB_REAL dx = p.x - r.x, dy = p.y - r.y, dz = p.z - r.z;
  if (!(dx * dx + dy * dy + dz * dz < trigger2)) {
    gate[0] = 1;
    if (slices > 0) {
      SEMLB_REAL f = floor((p.x - x0) * inv_width);
      moved[!(f >= 0) ? 0 : (f >= slices ? slices - 1 : (int)f)] = 1;
    }
  }
}

/* Gated, one item per slice, before nl_done: a build is due, the stats[1]-th since construction; the slices whose
   elements triggered it (nl_check's moved) get bit min(stats[1] - base, 30) of their mask, `base` being the build
   count at the start of the recording's interval (NeighbourList::take_triggers), and moved is cleared. */
__kernel void nl_mark(__global const int* gate, __global const int* stats, __global int* moved, __global int* bits,
                      int base, int slices) {
  int k = get_global_id(0);
  if (k >= slices || !gate[0]) return;
  if (moved[k]) {
    bits[k] |= 1 << min(stats[1] - base, 30);
    moved[k] = 0;
  }
}

/* Gated build: for each sorted slot, the sorted slots within the list radius (r^2 < list2; a NaN distance counts
   as within, as in semlb_pair_force) among the (2 SEMLB_NL_REACH + 1)^3 bins around its own, itself excluded (with
   SEMLB_NEWTON those after it alone); the first kmax are stored, 8 at a time (a chunk gathered in registers, then one
   32-byte store). stats[0] = the largest count (atomic_max), read by the host to size kmax. */
__kernel void nl_build(__global const int* gate, __global const real4* sorted_pos, __global const int* starts, real4 lo,
                       real4 size, int4 dims, SEMLB_REAL list2, int n, int kmax, __global int* nl_count,
                       __global int* nl, __global int* stats) {
  if (!gate[0]) return;
  SEMLB_FOR_ITEMS(s, n) {
    real4 me = sorted_pos[s];
    int4 b = bin3(me, lo, size, dims);
    int count = 0;
    const int8 lane = (int8)(0, 1, 2, 3, 4, 5, 6, 7);
    int8 chunk = (int8)(0);
    SEMLB_STENCIL_ROWS_REACH(b.x, b.y, b.z, dims.x, dims.y, dims.z, SEMLB_NL_REACH, first_bin, last_bin) {
      int last = starts[last_bin + 1];
#ifdef SEMLB_NEWTON
      for (int j = max(starts[first_bin], s + 1); j < last; ++j) { /* the half list: partners after s */
#else
      for (int j = starts[first_bin]; j < last; ++j) {
#endif
        real4 q = sorted_pos[j];
        SEMLB_REAL dx = me.x - q.x, dy = me.y - q.y, dz = me.z - q.z;
        if (j == s || dx * dx + dy * dy + dz * dz >= list2) continue;
        if (count < kmax) {
          chunk = select(chunk, (int8)(j), lane == (int8)(count & 7));
          if ((count & 7) == 7) vstore8(chunk, 0, nl + NL_AT(s, count >> 3, kmax));
        }
        ++count;
      }
    }
    if (count < kmax && (count & 7)) vstore8(chunk, 0, nl + NL_AT(s, count >> 3, kmax)); /* the last, partial chunk */
    nl_count[s] = count;
    if (count > ((volatile __global int*)stats)[0]) atomic_max(&stats[0], count); /* rarely: one address for all */
  }
}

/* Gated, one item: the build is done (gate[0] = 0) and counted (stats[1]). */
__kernel void nl_done(__global int* gate, __global int* stats) {
  if (!gate[0]) return;
  gate[0] = 0;
  ++stats[1];
}

/* Adds a sum acc (three fixed-point force components, then the bound) to element i's: with SEMLB_NEWTON atomically
   (the half list's slots add to their partners too), and not at all when nothing was added (acc[3], a pair's bound, is
   at least 1); otherwise a plain add (slot s alone writes its element). */
static inline void nl_add(__global long* force, __global long* bound, int i, const long* acc) {
#ifdef SEMLB_NEWTON
  if (acc[3] == 0) return;
  atom_add(&force[3 * i], acc[0]);
  atom_add(&force[3 * i + 1], acc[1]);
  atom_add(&force[3 * i + 2], acc[2]);
  atom_add(&bound[i], acc[3]);
#else
  force[3 * i] += acc[0];
  force[3 * i + 1] += acc[1];
  force[3 * i + 2] += acc[2];
  bound[i] += acc[3];
#endif
}

/* The pair of element i (at me, its info, sorted slot s) and sorted slot j: its force on i into acc and, with
   SEMLB_NEWTON, its force on j added to j's sums at once. */
static inline void nl_pair(int i, real4 me, int info, int j, __global const real4* sorted_pos,
                           __global const int* sorted_index, __global const ulong* keys,
                           __constant const SEMLB_REAL* table, SEMLB_REAL cutoff2, long* acc, __global long* force,
                           __global long* bound) {
  real4 q = sorted_pos[j];
#ifdef SEMLB_NEWTON
  int k = sorted_index[j];
  long acc_j[4] = {0, 0, 0, 0};
  if (semlb_pair_force_newton(me.x - q.x, me.y - q.y, me.z - q.z, info, INFO(q.w), table, cutoff2, acc, acc_j) < 0) {
    semlb_coincident_force(keys[i], keys[k], info, INFO(q.w), table, acc);
    semlb_coincident_force(keys[k], keys[i], INFO(q.w), info, table, acc_j);
  }
  nl_add(force, bound, k, acc_j);
#else
  if (semlb_pair_force(me.x - q.x, me.y - q.y, me.z - q.z, info, INFO(q.w), table, cutoff2, acc) < 0)
    semlb_coincident_force(keys[i], keys[sorted_index[j]], info, INFO(q.w), table, acc);
#endif
}

/* A slot over kmax: the exact stencil (reach SEMLB_NL_REACH) of the build's bins around its position at the build,
   ref[s] (bins of edge >= (cutoff + skin) / reach: every partner within the cutoff now was within cutoff + skin then,
   hence in those bins); with SEMLB_NEWTON its pairs with the slots after it alone, as the half list. */
static inline void nl_stencil(int s, int i, real4 me, __global const real4* sorted_pos, __global const real4* ref,
                              __global const int* sorted_index, __global const ulong* keys, __global const int* starts,
                              real4 lo, real4 size, int4 dims, __constant const SEMLB_REAL* table, SEMLB_REAL cutoff2,
                              long* acc, __global long* force, __global long* bound) {
  int4 b = bin3(ref[s], lo, size, dims);
#ifdef SEMLB_NEWTON
  int info = INFO(me.w);
  SEMLB_STENCIL_ROWS_REACH(b.x, b.y, b.z, dims.x, dims.y, dims.z, SEMLB_NL_REACH, first_bin, last_bin) {
    int last = starts[last_bin + 1];
    for (int j = max(starts[first_bin], s + 1); j < last; ++j)
      nl_pair(i, me, info, j, sorted_pos, sorted_index, keys, table, cutoff2, acc, force, bound);
  }
#else
  stencil_forces(me, i, s, b, dims, SEMLB_NL_REACH, sorted_pos, sorted_index, starts, keys, table, cutoff2, acc);
#endif
}

/* Local pair forces (owned on owned) over the list on sorted slot s of the build. Every listed pair goes
   through semlb_pair_force, which keeps those within the cutoff now: the same pairs and the same fixed-point sums
   as the stencil and as all pairs, as long as no element moved by more than the trigger since the build. A slot
   over kmax takes nl_stencil instead. */
static inline void nl_slot_forces(int s, __global const real4* sorted_pos, __global const real4* ref,
                                  __global const int* sorted_index, __global const ulong* keys,
                                  __global const int* nl_count, __global const int* nl, int kmax,
                                  __global const int* starts, real4 lo, real4 size, int4 dims,
                                  __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force,
                                  __global long* bound) {
  real4 me = sorted_pos[s];
  int i = sorted_index[s], info = INFO(me.w), count = nl_count[s];
  SEMLB_REAL cutoff2 = cutoff * cutoff;
  long acc[4] = {0, 0, 0, 0};
  if (count <= kmax) {
    /* 4 partners per load (an int4 of the slot's chunk), then the force law on each */
    for (int base = 0; base < count; base += 4) {
      int4 v = vload4(0, nl + NL_AT(s, base >> 3, kmax) + (base & 7));
      int m = min(4, count - base);
      for (int k = 0; k < m; ++k)
        nl_pair(i, me, info, k == 0 ? v.x : (k == 1 ? v.y : (k == 2 ? v.z : v.w)), sorted_pos, sorted_index, keys,
                table, cutoff2, acc, force, bound);
    }
  } else {
#ifdef SEMLB_NL_SPLIT
    return; /* nl_overflow's */
#else
    nl_stencil(s, i, me, sorted_pos, ref, sorted_index, keys, starts, lo, size, dims, table, cutoff2, acc, force,
               bound);
#endif
  }
  nl_add(force, bound, i, acc);
}

#ifdef SEMLB_NL_GROUP_SORT
/* A variant (-DSEMLB_NL_GROUP_SORT, to measure; docs/performance.md "Slots grouped by list length"): a warp's loop
   runs as long as its longest list, so each work-group of NL_SORT_GROUP slots (nl_forces' group: the host's kGroup)
   hands its slots to its items longest list first, sorted in local memory (bitonic, descending by count, ties by
   slot). The same slots in the same group, so the list's loads stay within the group's warps; each slot still runs
   once, and the fixed-point sums make the forces the same bit for bit. Returns the slot of item `lid`. nl_forces
   requires NL_SORT_GROUP items per group (reqd_work_group_size: another launch fails rather than drop slots). */
#define NL_SORT_GROUP 128
static inline int nl_group_sorted_slot(__global const int* nl_count, int n, __local int* key) {
  int lid = get_local_id(0), first = get_group_id(0) * NL_SORT_GROUP, s = first + lid;
  /* (count + 1) NL_SORT_GROUP + (NL_SORT_GROUP - 1 - lid): unique, >= 0, an item past n (count -1) last */
  key[lid] = (s < n ? min(nl_count[s], 1 << 22) + 1 : 0) * NL_SORT_GROUP + (NL_SORT_GROUP - 1 - lid);
  for (int k = 2; k <= NL_SORT_GROUP; k <<= 1)
    for (int j = k >> 1; j > 0; j >>= 1) {
      barrier(CLK_LOCAL_MEM_FENCE);
      int p = lid ^ j;
      if (p > lid) {
        int a = key[lid], b = key[p];
        if ((lid & k) == 0 ? a < b : a > b) { /* descending where bit k is clear: the whole group descending */
          key[lid] = b;
          key[p] = a;
        }
      }
    }
  barrier(CLK_LOCAL_MEM_FENCE);
  return first + NL_SORT_GROUP - 1 - key[lid] % NL_SORT_GROUP;
}
#define NL_FORCES_GROUP __attribute__((reqd_work_group_size(NL_SORT_GROUP, 1, 1)))
#else
#define NL_FORCES_GROUP
#endif

/* The local pair forces over the list: one item per sorted slot of the build. */
__kernel NL_FORCES_GROUP void nl_forces(__global const real4* sorted_pos, __global const real4* ref,
                                        __global const int* sorted_index, __global const ulong* keys,
                                        __global const int* nl_count, __global const int* nl, int kmax,
                                        __global const int* starts, real4 lo, real4 size, int4 dims,
                                        __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force,
                                        __global long* bound, int n) {
#ifdef SEMLB_NL_GROUP_SORT
  __local int key[NL_SORT_GROUP];
  int s = nl_group_sorted_slot(nl_count, n, key);
#else
  int s = get_global_id(0);
#endif
  if (s >= n) return;
  nl_slot_forces(s, sorted_pos, ref, sorted_index, keys, nl_count, nl, kmax, starts, lo, size, dims, table, cutoff,
                 force, bound);
}

/* The same for the sorted slots items[first .. first + n) alone (the measured cost of a region of the tissue,
   docs/measured_time.md; `force` and `bound` are scratch buffers there). */
__kernel void nl_forces_items(__global const real4* sorted_pos, __global const real4* ref,
                              __global const int* sorted_index, __global const ulong* keys,
                              __global const int* nl_count, __global const int* nl, int kmax,
                              __global const int* starts, real4 lo, real4 size, int4 dims,
                              __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force,
                              __global long* bound, __global const int* items, int first, int n) {
  int k = get_global_id(0);
  if (k >= n) return;
  nl_slot_forces(items[first + k], sorted_pos, ref, sorted_index, keys, nl_count, nl, kmax, starts, lo, size, dims,
                 table, cutoff, force, bound);
}

/* A variant (-DSEMLB_NL_SPLIT, to measure): the slots over kmax in a kernel of their own, so that nl_forces holds
   only the list loop's registers; without it this kernel returns at once (the host launches it always). */
__kernel void nl_overflow(__global const real4* sorted_pos, __global const real4* ref, __global const int* sorted_index,
                          __global const ulong* keys, __global const int* nl_count, int kmax,
                          __global const int* starts, real4 lo, real4 size, int4 dims,
                          __constant const SEMLB_REAL* table, SEMLB_REAL cutoff, __global long* force,
                          __global long* bound, int n) {
#ifdef SEMLB_NL_SPLIT
  int s = get_global_id(0);
  if (s >= n || nl_count[s] <= kmax) return;
  real4 me = sorted_pos[s];
  int i = sorted_index[s];
  long acc[4] = {0, 0, 0, 0};
  nl_stencil(s, i, me, sorted_pos, ref, sorted_index, keys, starts, lo, size, dims, table, cutoff * cutoff, acc, force,
             bound);
  nl_add(force, bound, i, acc);
#endif
}
