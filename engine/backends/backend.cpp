// Backend registry and the bin grid shared by every binned backend.
#include "backend.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/errors.hpp"
#include "common/registry.hpp"
#include "effects/effect.hpp"
#include "model/tissue.hpp"
#include "removal/removal.hpp"

namespace semlb::engine {
namespace {
Registry<BackendFactory>& registry() {
  static Registry<BackendFactory> r;
  return r;
}
}  // namespace

Grid Grid::cover(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cutoff) {
  Grid g;
  g.lo = lo;
  for (int d = 0; d < 3; ++d) {
    const double extent = std::max(hi[d] - lo[d], cutoff * (1 + 1e-4));
    // 1e-4 of slack keeps bins >= cutoff even after float rounding of positions on a device
    g.dims[d] = std::max(1, static_cast<int>(std::floor(extent / (cutoff * (1 + 1e-4)))));
    g.size[d] = extent / g.dims[d];
  }
  if (g.bins() > (1L << 31) - 2) throw InputError("domain: " + std::to_string(g.bins()) + " bins exceed 2^31; enlarge the cutoff or shrink the box");
  return g;
}

std::array<int, 3> Grid::bin_of(const double* p) const {
  std::array<int, 3> b{};
  for (int d = 0; d < 3; ++d) {
    const double x = std::floor((p[d] - lo[d]) / size[d]);
    b[d] = !(x >= 0) ? 0 : (x >= dims[d] ? dims[d] - 1 : static_cast<int>(x));  // NaN -> bin 0
  }
  return b;
}

std::string Failure::quantity() const {
  return code == 1 ? "position is not finite" : "displacement exceeds time.max_displacement";
}

BackendRegistrar::BackendRegistrar(const std::string& name, BackendFactory factory) {
  registry().add(name, std::move(factory));
}

std::vector<std::string> backend_names() { return registry().names(); }

std::unique_ptr<Backend> make_backend(const BackendConfig& config) {
  const BackendFactory* factory = registry().find(config.name);
  if (!factory) throw InputError("backend '" + config.name + "' is unknown (known: " + registry().known() + ")");
  return (*factory)(config);
}

Traffic Backend::traffic_total() const {
  Traffic t;
  for (const auto& [phase, bytes] : traffic_) t.h2d += bytes.h2d, t.d2h += bytes.d2h;
  return t;
}

std::vector<double> Backend::slice_work(State& host, const SliceMap& map, const Grid& g, const CountReduce& reduce) {
  download(host);
  auto counts = bin_counts(host, g);
  if (reduce) reduce(counts);
  return cell_work(host, g, counts, map);
}

void Backend::take_leavers(State& host, const SliceMap& map, const std::vector<int>& boundaries, int rank, State& leavers,
                           std::vector<int>& owner) {
  download(host);
  owner.clear();
  State stay;
  split_by_owner(host, map, boundaries, rank, stay, &leavers, &owner);
  if (leavers.cells() == 0) return;  // the backend holds exactly these cells
  host = std::move(stay);
  upload(host);
}

long Backend::remove_cells(State& host, const std::string& rule, const std::vector<double>& params) {
  const RemovalEvaluator removes = removal_rule(rule).removes;
  download(host);
  State kept;
  kept.step = host.step;
  kept.time = host.time;
  for (const auto& [name, f] : host.cell_fields) kept.cell_fields[name];
  long removed = 0;
  for (long c = 0; c < host.cells(); ++c) {
    double ctr[3];
    cellrules::semlb_cell_centroid(host.position.data(), host.cell_first[c], host.cell_count[c], ctr);
    if (removes(ctr[0], ctr[1], ctr[2], host.cell_type[c], host.cell_count[c], params.data())) ++removed;
    else copy_cell(host, c, kept);
  }
  if (removed == 0) return 0;  // the backend holds exactly these cells
  kept.reindex();
  host = std::move(kept);
  upload(host);
  return removed;
}

void Backend::append_cells(State& host, const State& arrivals) {
  download(host);
  for (long c = 0; c < arrivals.cells(); ++c) copy_cell(arrivals, c, host);
  host.reindex();
  upload(host);
}

int SliceMap::slice_of(double x) const {
  const double f = std::floor((x - x0) / width);
  return !(f >= 0) ? 0 : (f >= slices ? slices - 1 : static_cast<int>(f));
}

int owner_of(int slice, const std::vector<int>& boundaries) {
  return static_cast<int>(std::upper_bound(boundaries.begin(), boundaries.end(), slice) - boundaries.begin());
}

void split_by_owner(const State& s, const SliceMap& map, const std::vector<int>& boundaries, int rank, State& stay,
                    State* leave, std::vector<int>* owner) {
  for (State* to : {&stay, leave}) {
    if (!to) continue;
    *to = {};
    to->step = s.step;
    to->time = s.time;
    for (const auto& [name, f] : s.cell_fields) to->cell_fields[name];
  }
  for (long c = 0; c < s.cells(); ++c) {
    const int o = owner_of(map.slice_of(centroid(s, c)[0]), boundaries);
    if (o == rank) {
      copy_cell(s, c, stay);
    } else if (leave) {
      copy_cell(s, c, *leave);
      owner->push_back(o);
    }
  }
  stay.reindex();
  if (leave) leave->reindex();
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
long bin_index(const Grid& g, const std::array<int, 3>& b) { return (static_cast<long>(b[2]) * g.dims[1] + b[1]) * g.dims[0] + b[0]; }
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
    long n_near = 0;
    for (int z = std::max(b[2] - 1, 0); z <= std::min(b[2] + 1, g.dims[2] - 1); ++z)
      for (int y = std::max(b[1] - 1, 0); y <= std::min(b[1] + 1, g.dims[1] - 1); ++y)
        for (int x = std::max(b[0] - 1, 0); x <= std::min(b[0] + 1, g.dims[0] - 1); ++x) n_near += counts[bin_index(g, {x, y, z})];
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
