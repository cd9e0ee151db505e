// Decomposition settings, the per-slice workload W_s (paper eqs. 2-3) and slab ownership.
#include "decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "backends/backend.hpp"
#include "common/errors.hpp"
#include "effects/effect.hpp"
#include "model/tissue.hpp"

namespace semlb::engine {

Decomposition Decomposition::from_scene(const Scene& scene, int ranks) {
  Decomposition d;
  const Section& s = *scene.decomposition;
  const double extent = scene.box_hi[0] - scene.box_lo[0];
  const double slice_um = s.real("slice_width", scene.cutoff / 4, 1e-6, 1e9);
  const double min_um = s.real("min_width", 3 * scene.cutoff, 0, 1e9);
  d.slices = std::max(1, static_cast<int>(std::ceil(extent / slice_um)));
  d.x0 = scene.box_lo[0];
  d.width = extent / d.slices;
  d.min_width = std::max(1, static_cast<int>(std::ceil(min_um / d.width)));
  d.policy = s.text("policy", d.policy);
  d.initial = s.text("initial", d.initial);
  if (d.initial != "workload" && d.initial != "uniform") s.fail("initial", "must be workload or uniform");
  d.rebalance_every = s.integer("rebalance_every", d.rebalance_every, 1, 1L << 40);
  d.timing = s.text("timing", d.timing);
  if (d.timing != "measured" && d.timing != "modelled") s.fail("timing", "must be measured or modelled");
  const Section p = s.child("params");
  for (const auto& k : p.keys()) d.params.set(k, p.text(k, ""));
  p.finish();
  s.finish();
  // On 3 or more ranks the ghost exchange, which reaches the neighbouring ranks only, needs slabs at least as
  // wide as the cutoff plus a cell's reach (taken as one cutoff) on either side. exchange_ghosts() still
  // checks the elements at every step and stops the run if a cell reaches further.
  const int ghost_slices = static_cast<int>(std::ceil(3 * scene.cutoff / d.width));
  if (ranks >= 3 && d.min_width < ghost_slices) {
    std::ostringstream m;
    m << min_um << " um is " << d.min_width << " slices of " << d.width << " um, narrower than the ghost region on "
      << ranks << " ranks: the cutoff plus a cell's reach of one cutoff on either side, 3 x " << scene.cutoff
      << " um = " << ghost_slices << " slices (the default); use at most 2 ranks or a wider min_width";
    s.fail("min_width", m.str());
  }
  if (ranks >= 2 && d.slices < ranks * d.min_width)  // one rank holds the whole domain, however narrow
    s.fail("min_width", std::to_string(ranks) + " ranks need " + std::to_string(ranks * d.min_width) + " slices of " +
                            std::to_string(d.width) + " um but the domain has " + std::to_string(d.slices) +
                            ": use fewer ranks or a larger tissue");
  try {
    check_engine_policy(d.policy);
    make_policy(d.policy, d.params);
  } catch (const InputError& e) {
    s.fail("policy", e.what());
  }
  return d;
}

void check_engine_policy(const std::string& policy) {
  if (policy_needs(policy).true_work)  // the engine measures times and W_s (slice_work); only the surrogate knows the future
    throw InputError("'" + policy + "' needs the true work of the next interval, which a simulation cannot know "
                     "(a surrogate baseline: use it with semlb surrogate)");
}

int Decomposition::slice_of(double x) const {
  const double f = std::floor((x - x0) / width);
  return !(f >= 0) ? 0 : (f >= slices ? slices - 1 : static_cast<int>(f));
}

int owner_of(int slice, const std::vector<int>& boundaries) {
  return static_cast<int>(std::upper_bound(boundaries.begin(), boundaries.end(), slice) - boundaries.begin());
}

std::vector<double> slice_workload(const State& s, const std::vector<double>& ghosts, const Decomposition& d,
                                   double cutoff) {
  const auto [lo, hi] = tissue_box(s, cutoff);
  const Grid g = Grid::cover(lo, hi, cutoff);
  auto index = [&](const std::array<int, 3>& b) { return (static_cast<long>(b[2]) * g.dims[1] + b[1]) * g.dims[0] + b[0]; };
  // Elements per bin: dense while the grid is at most a few times the elements, else sorted bin indices.
  const long elements = static_cast<long>((s.position.size() + ghosts.size()) / 3);
  const bool dense = g.bins() <= 4 * elements + (1L << 20);
  std::vector<long> count(dense ? g.bins() : 0), bins;
  for (const auto* positions : {&s.position, &ghosts})
    for (size_t e = 0; e < positions->size(); e += 3) {
      const long b = index(g.bin_of(&(*positions)[e]));
      dense ? static_cast<void>(++count[b]) : bins.push_back(b);
    }
  std::sort(bins.begin(), bins.end());
  auto in_bin = [&](long b) {
    if (dense) return count[b];
    const auto [first, last] = std::equal_range(bins.begin(), bins.end(), b);
    return static_cast<long>(last - first);
  };
  std::vector<double> w(d.slices, 0.0);
  for (long c = 0; c < s.cells(); ++c) {
    const auto ctr = centroid(s, c);
    const auto b = g.bin_of(ctr.data());
    long n_near = 0;
    for (int z = std::max(b[2] - 1, 0); z <= std::min(b[2] + 1, g.dims[2] - 1); ++z)
      for (int y = std::max(b[1] - 1, 0); y <= std::min(b[1] + 1, g.dims[1] - 1); ++y)
        for (int x = std::max(b[0] - 1, 0); x <= std::min(b[0] + 1, g.dims[0] - 1); ++x) n_near += in_bin(index({x, y, z}));
    w[d.slice_of(ctr[0])] += static_cast<double>(s.cell_count[c]) * static_cast<double>(n_near);  // w_i = n_i n_N(i)
  }
  return w;
}

}  // namespace semlb::engine
