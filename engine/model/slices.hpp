// The maps of the decomposition and of the bins, and the per-slice workload W_s, on the host: the bin grid, the
// slices along x, slice owners, the ownership split of cells; their arithmetic is physics/slices.h, which
// the W_s and migration kernels (backends/cells.cl) use too.
#pragma once
#include <array>
#include <functional>
#include <vector>

#include "model/state.hpp"

namespace semlb::engine {

// The box that bins cover. Elements outside are clamped into the edge bins, which keeps every pair
// within the cutoff in neighbouring bins (clamping is 1-Lipschitz in bin units).
struct Grid {
  std::array<double, 3> lo{}, size{};  // bin edge length >= cutoff
  std::array<int, 3> dims{1, 1, 1};
  // The most bins a grid has (2^24): bin counts and starts are 32-bit on the devices, and a bin sort allocates and
  // scans one start per bin at every step, so a far-flung element must not ask for billions of them.
  static constexpr long kMaxBins = 1L << 24;
  long bins() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
  // Bins of edge >= cutoff (um) over [lo, hi], at most kMaxBins of them: past that, fewer and larger bins.
  static Grid cover(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cutoff);
  std::array<int, 3> bin_of(const double* p) const;
};

// The slices along x that the decomposition balances (decomposition/decomposition.hpp derives from it): slice s
// covers [x0 + s width, x0 + (s+1) width) um; x outside is clamped into the first or last slice, NaN into 0.
struct SliceMap {
  int slices = 0;
  double x0 = 0, width = 1;
  int slice_of(double x) const;
};
// The rank that owns slice `slice`: the number of interior boundaries at or below it.
int owner_of(int slice, const std::vector<int>& boundaries);
// The ownership rule of cells (docs/engine.md): the rank owning the slice of the cell's centroid. Copies the
// cells of `s` that `rank` owns into `stay` and, if `leave` is given, the others into `*leave` with their owners
// appended to `*owner`; keeps their order, carries the step, time and field names, reindexes both.
void split_by_owner(const State& s, const SliceMap& map, const std::vector<int>& boundaries, int rank, State& stay,
                    State* leave = nullptr, std::vector<int>* owner = nullptr);

// Per-slice workload W_s = sum over cells of w_i = n_i * n_N(i) (paper eqs. 2-3), one rule for one device and any
// number of ranks (docs/engine.md "Workload score"): the bins are cubes of at least the cutoff over the padded box of
// the WHOLE tissue (work_grid of every rank's elements' bounding box), n_N(i) counts every element of the tissue in
// the 3x3x3 bins around the bin of cell i's centroid (on P ranks: each rank counts its owned elements, the counts are
// summed over ranks), and w_i is added into the slice of the centroid. Integer counts: the same tissue gives the same
// W_s bit for bit whatever the partition and the rank count.
inline constexpr long kMaxWorkBins = 1L << 27;  // dense int32 counts: 512 MiB
// The W_s grid over the elements' bounding box [lo, hi] (um): padded_box, then Grid::cover. InputError when it would
// have more than kMaxWorkBins bins (a tissue spread over a box far larger than its cells), naming the box.
Grid work_grid(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cutoff);
// Elements of `s` per bin of `g` (g.bins() entries, bin index (z * ny + y) * nx + x).
std::vector<int> bin_counts(const State& s, const Grid& g);
// W_s of the cells of `s` (d.slices entries) given `counts`, the elements per bin of the whole tissue.
std::vector<double> cell_work(const State& s, const Grid& g, const std::vector<int>& counts, const SliceMap& d);
// W_s of a whole tissue on one device: work_grid over its elements, bin_counts, cell_work.
std::vector<double> slice_workload(const State& cells, const SliceMap& d, double cutoff);
// Sums a bin-count array over the ranks in place (Mpi::allreduce_sum); empty: one device, nothing to sum.
using CountReduce = std::function<void(std::vector<int>&)>;

}  // namespace semlb::engine
