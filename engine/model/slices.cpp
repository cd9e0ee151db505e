// The bin grid, the slices, their owners, the ownership split and W_s on the host (slices.hpp); the arithmetic
// from slices.h, shared with the kernels.
#include "slices.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "physics/cpu_physics.hpp"
#include "common/errors.hpp"
#include "model/tissue.hpp"

namespace semlb::engine {
namespace arith {
#define SEMLB_FLOOR std::floor
#define SEMLB_GLOBAL
#include "physics/slices.h"
#undef SEMLB_FLOOR
#undef SEMLB_GLOBAL
}  // namespace arith

Grid Grid::cover(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cutoff) {
  // 1e-4 of slack keeps bins >= cutoff even after float rounding of positions on a device
  const double edge = cutoff * (1 + 1e-4), limit = static_cast<double>(kMaxBins);
  std::array<double, 3> extent{}, n{};
  for (int d = 0; d < 3; ++d) {
    extent[d] = std::max(hi[d] - lo[d], edge);
    n[d] = std::min(limit, std::max(1.0, std::floor(extent[d] / edge)));  // in doubles: no int overflow on the way
  }
  // More bins than a 32-bit sort counts (a far-flung element, a huge box): fewer, larger bins, the largest count
  // first; bins of edge >= cutoff are all the pair loops need, so the forces stay the same sums.
  for (int pass = 0; pass < 3 && n[0] * n[1] * n[2] > limit; ++pass) {
    const int big = static_cast<int>(std::max_element(n.begin(), n.end()) - n.begin());
    n[big] = std::max(1.0, std::floor(limit / (n[0] * n[1] * n[2] / n[big])));
  }
  Grid g;
  g.lo = lo;
  for (int d = 0; d < 3; ++d) {
    g.dims[d] = static_cast<int>(n[d]);
    g.size[d] = extent[d] / g.dims[d];
  }
  return g;
}

std::array<int, 3> Grid::bin_of(const double* p) const {
  std::array<int, 3> b{};
  for (int d = 0; d < 3; ++d) b[d] = arith::semlb_bin_of(p[d], lo[d], size[d], dims[d]);  // NaN -> bin 0
  return b;
}

int SliceMap::slice_of(double x) const { return arith::semlb_slice_of(x, x0, width, slices); }

int owner_of(int slice, const std::vector<int>& boundaries) {
  return arith::semlb_owner_of(slice, boundaries.data(), static_cast<int>(boundaries.size()));
}

void split_by_owner(const State& s, const SliceMap& map, const std::vector<int>& boundaries, int rank, State& stay,
                    State* leave, std::vector<int>* owner) {
  std::vector<long> stays, leaves;
  for (long c = 0; c < s.cells(); ++c) {
    const int o = owner_of(map.slice_of(centroid(s, c)[0]), boundaries);
    if (o == rank) {
      stays.push_back(c);
    } else if (leave) {
      leaves.push_back(c);
      owner->push_back(o);
    }
  }
  stay = empty_like(s);
  copy_cells(s, stays, stay);
  stay.reindex();
  if (leave) {
    *leave = empty_like(s);
    copy_cells(s, leaves, *leave);
    leave->reindex();
  }
}

Grid work_grid(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cutoff) {
  const auto [plo, phi] = padded_box(lo, hi, cutoff);
  const Grid g = Grid::cover(plo, phi, cutoff);
  if (g.bins() > kMaxWorkBins) {
    std::ostringstream m;
    m << "workload score: the tissue spans [" << lo[0] << ", " << hi[0] << "] x [" << lo[1] << ", " << hi[1] << "] x ["
      << lo[2] << ", " << hi[2] << "] um, " << g.bins() << " bins of the cutoff (more than " << kMaxWorkBins
      << "); a tissue this sparse needs a larger cutoff";
    throw InputError(m.str());
  }
  return g;
}

namespace {
long bin_index(const Grid& g, const std::array<int, 3>& b) {
  return (static_cast<long>(b[2]) * g.dims[1] + b[1]) * g.dims[0] + b[0];
}
}  // namespace

std::vector<int> bin_counts(const State& s, const Grid& g) {
  std::vector<int> count(g.bins(), 0);
  for (long e = 0; e < s.elements(); ++e) ++count[bin_index(g, g.bin_of(&s.position[3 * e]))];
  return count;
}

std::vector<double> cell_work(const State& s, const Grid& g, const std::vector<int>& counts, const SliceMap& d) {
  std::vector<double> w(d.slices, 0.0);
  for (long c = 0; c < s.cells(); ++c) {
    const auto ctr = centroid(s, c);
    const auto b = g.bin_of(ctr.data());
    const long n_near = arith::semlb_near_count(counts.data(), b[0], b[1], b[2], g.dims[0], g.dims[1], g.dims[2]);
    w[d.slice_of(ctr[0])] += static_cast<double>(s.cell_count[c]) * static_cast<double>(n_near);  // w_i = n_i n_N(i)
  }
  return w;
}

std::vector<double> slice_workload(const State& s, const SliceMap& d, double cutoff) {
  const auto [lo, hi] = element_bounds(s);
  const Grid g = work_grid(lo, hi, cutoff);
  return cell_work(s, g, bin_counts(s, g), d);
}

}  // namespace semlb::engine
