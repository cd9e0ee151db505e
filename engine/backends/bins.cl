/* Counting sort of elements into bins, the one used by the per-step stencil and the neighbour list's builds: bin
   coordinates, per-bin counts, the 3-kernel exclusive scan, the scatter (kernels.cl includes it). */
/* Bin coordinates clamped into the grid (x fastest); clamped as reals first, so NaN lands in bin 0. */
static inline int bin1(SEMLB_REAL x, SEMLB_REAL lo, SEMLB_REAL size, int dim) {
  return (int)fmin(fmax(floor((x - lo) / size), (SEMLB_REAL)0), (SEMLB_REAL)(dim - 1));
}
static inline int4 bin3(real4 p, real4 lo, real4 size, int4 dims) {
  return (int4)(bin1(p.x, lo.x, size.x, dims.x), bin1(p.y, lo.y, size.y, dims.y), bin1(p.z, lo.z, size.z, dims.z), 0);
}

/* Items of a grid-stride kernel: the loop visits [0, n) whatever the launch size. */
#define SEMLB_FOR_ITEMS(i, n) for (int i = get_global_id(0); i < (n); i += get_global_size(0))

/* Elements [first, first + n): bin[k] the bin of element first + k; counts[bin] incremented. Gated, as the scan:
   nothing unless gate[0] is set (the per-step sort passes a buffer that always is; the neighbour list's flag). */
__kernel void bin_count(__global const int* gate, __global const real4* pos, int first, int n, real4 lo, real4 size,
                        int4 dims, __global int* bin, __global int* counts) {
  if (!gate[0]) return;
  SEMLB_FOR_ITEMS(i, n) {
    int4 b = bin3(pos[first + i], lo, size, dims);
    int k = (b.z * dims.y + b.y) * dims.x + b.x;
    bin[i] = k;
    atomic_inc(&counts[k]);
  }
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
__kernel void scan_blocks(__global const int* gate, __global const int* counts, __global int* starts,
                          __global int* sums, int nbins, __local int* tmp) {
  if (!gate[0]) return; /* gate: the scan kernels run only when its first int is set (neighbour_list.cl) */
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
   sorted_index holds the element index (first + k); ref, unless null, a second copy of the sorted positions (the
   neighbour list's positions at its build). Gated as bin_count. */
__kernel void scatter(__global const int* gate, __global const real4* pos, int first, __global const int* bin,
                      __global int* cursor, __global real4* sorted_pos, __global int* sorted_index, __global real4* ref,
                      int n) {
  if (!gate[0]) return;
  SEMLB_FOR_ITEMS(i, n) {
    int s = atomic_inc(&cursor[bin[i]]);
    real4 p = pos[first + i];
    sorted_pos[s] = p;
    sorted_index[s] = first + i;
    if (ref) ref[s] = p;
  }
}
