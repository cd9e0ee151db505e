// Epidermal sheet generator: cells on staggered hexagonal layers above the basement membrane (z = 0),
// each with elements_min..elements_max elements (mean ~15) scattered in a ball inside the cell.
#include "tissue.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <tuple>

#include "physics/cpu_physics.hpp"
#include "common/text_io.hpp"

namespace semlb::engine {
namespace {

constexpr uint64_t kTissueStream = 0x7469737375ULL;

// The epidermal_sheet generator's tissue keys, read and checked.
struct Sheet {
  long cells, layers;
  double radius, spacing, spread;
  int emin, emax;
};
Sheet sheet_settings(const Section& t) {
  Sheet g;
  g.cells = t.integer("cells", 60, 1, 1L << kRootIdBits);
  g.layers = t.integer("layers", 2, 1, 1000);
  g.radius = t.real("cell_radius", 5.0, 1e-6, 1e6);
  g.spacing = t.real("spacing", 1.8 * g.radius, 1e-6, 1e6);
  g.spread = t.real("spread", 0.6 * g.radius, 0, 1e6);
  g.emin = static_cast<int>(t.integer("elements_min", 10, 1, kMaxSlots - 1));
  g.emax = static_cast<int>(t.integer("elements_max", 20, 1, kMaxSlots - 1));
  if (g.emax < g.emin) t.fail("elements_max", "must be >= elements_min");
  return g;
}

State epidermal_sheet(const Sheet& g, uint64_t seed) {
  const long cells = g.cells, layers = g.layers;
  const double radius = g.radius, spacing = g.spacing, spread = g.spread;
  const int emin = g.emin, emax = g.emax;
  const long per_layer = (cells + layers - 1) / layers;
  const long nx = static_cast<long>(std::ceil(std::sqrt(static_cast<double>(per_layer))));
  // Each cell's place and each element's offset depend only on (seed, cell, element): two passes, each parallel over
  // the cells (the element counts, then the positions at their prefix-sum offsets), give the same state on any
  // number of threads.
  const uint64_t stream = seed ^ kTissueStream;
  State s;
  s.cell_id.resize(cells);
  s.cell_type.resize(cells);
  s.cell_count.resize(cells);
#pragma omp parallel for schedule(static)
  for (long c = 0; c < cells; ++c) {
    const auto id = static_cast<uint64_t>(c);
    s.cell_id[c] = id;
    s.cell_type[c] = c / per_layer == 0 ? kBasal : kSpinous;
    s.cell_count[c] = std::min(emax, emin + static_cast<int>(uniform01(stream, id, 0, 0) * (emax - emin + 1)));
  }
  std::vector<long> first(cells + 1, 0);
  for (long c = 0; c < cells; ++c) first[c + 1] = first[c] + s.cell_count[c];
  s.position.resize(3 * static_cast<size_t>(first[cells]));
#pragma omp parallel for schedule(static)
  for (long c = 0; c < cells; ++c) {
    const long layer = c / per_layer, k = c % per_layer, i = k % nx, j = k / nx;
    const double stagger = layer % 2 ? 0.5 * spacing : 0.0;
    const double cx = (i + 0.5 * (j % 2)) * spacing + stagger,
                 cy = j * spacing * std::sqrt(3.0) / 2 + stagger / std::sqrt(3.0), cz = radius + layer * spacing * 0.85;
    for (int e = 0; e < s.cell_count[c]; ++e) {
      const uint64_t key = element_key(static_cast<uint64_t>(c), e);
      double u[3], norm = 0;
      for (int d = 0; d < 3; ++d) {
        u[d] = gaussian(stream, key, 1, d);
        norm += u[d] * u[d];
      }
      const double r = spread * std::cbrt(uniform01(stream, key, 2, 0)) / (std::sqrt(norm) + 1e-300);
      double* x = &s.position[3 * static_cast<size_t>(first[c] + e)];
      x[0] = cx + r * u[0];
      x[1] = cy + r * u[1];
      x[2] = std::max(cz + r * u[2], 0.5);
    }
  }
  s.reindex();
  return s;
}

}  // namespace

std::pair<std::array<double, 3>, std::array<double, 3>> element_bounds(const State& s) {
  std::array<double, 3> lo{}, hi{};
  for (int d = 0; d < 3; ++d) {
    double l = INFINITY, h = -INFINITY;
    for (long e = 0; e < s.elements(); ++e)
      if (const double x = s.position[3 * e + d]; std::isfinite(x)) l = std::fmin(l, x), h = std::fmax(h, x);
    lo[d] = l <= h ? l : 0.0;
    hi[d] = l <= h ? h : 0.0;
  }
  return {lo, hi};
}

std::pair<std::array<double, 3>, std::array<double, 3>> tissue_box(const State& s, double cutoff) {
  const auto [lo, hi] = element_bounds(s);
  return padded_box(lo, hi, cutoff);
}

std::pair<std::array<double, 3>, std::array<double, 3>> padded_box(std::array<double, 3> lo, std::array<double, 3> hi,
                                                                   double cutoff) {
  for (int d = 0; d < 3; ++d) {
    lo[d] -= cutoff;
    hi[d] += cutoff;
  }
  lo[2] = std::min(lo[2], -cutoff);
  hi[2] += 3 * cutoff;  // room for stratification
  return {lo, hi};
}

void fit_box(Scene& scene, const State& s) { std::tie(scene.box_lo, scene.box_hi) = tissue_box(s, scene.cutoff); }

namespace {
// A scene's tissue section, read and checked: the file or the generator's keys, and x_range. What make_tissue builds
// from, and all check_tissue reads.
struct TissueSpec {
  std::string file;                              // tissue.file as written (relative to the scene); empty: the generator
  std::optional<Sheet> sheet;                    // the epidermal_sheet generator's keys
  std::optional<std::array<double, 2>> x_range;  // um
};
TissueSpec tissue_spec(const Section& t) {
  TissueSpec spec;
  spec.file = t.text("file", "");
  const std::string generator = t.text("generator", spec.file.empty() ? "epidermal_sheet" : "");
  if (spec.file.empty()) {
    if (generator != "epidermal_sheet")
      t.fail("generator", "unknown generator '" + generator + "' (known: epidermal_sheet; or give tissue.file)");
    spec.sheet = sheet_settings(t);
  }
  // tissue.x_range: [lo, hi] keeps the cells whose centroid x lies in [lo, hi) um: one slab of the tissue (e.g. to time
  // a rank's slab alone on the device, docs/measured_time.md)
  if (t.has("x_range")) {
    const auto range = t.texts("x_range", {});
    if (range.size() != 2) t.fail("x_range", "must be [lo, hi] in um");
    spec.x_range = {parse_real(range[0], t.where("x_range")), parse_real(range[1], t.where("x_range"))};
    if (!((*spec.x_range)[0] < (*spec.x_range)[1])) t.fail("x_range", "lo must be below hi");
  }
  t.finish();
  return spec;
}
}  // namespace

void check_tissue(const Scene& scene) {
  const Section t = *scene.tissue;  // a copy: what it marks read is this check's
  tissue_spec(t);
}

State make_tissue(Scene& scene, const std::function<State(const std::string& path)>& read_file) {
  const Section& t = *scene.tissue;
  const TissueSpec spec = tissue_spec(t);
  State s;
  if (spec.sheet) {
    s = epidermal_sheet(*spec.sheet, scene.seed);
  } else {
    const auto path = std::filesystem::path(scene.path).parent_path() / spec.file;
    s = read_file(std::filesystem::path(spec.file).is_absolute() ? spec.file : path.string());
  }
  if (spec.x_range) {
    const auto [lo, hi] = *spec.x_range;
    std::vector<long> inside;
    for (long c = 0; c < s.cells(); ++c)
      if (const double x = centroid(s, c)[0]; x >= lo && x < hi) inside.push_back(c);
    State kept = empty_like(s);
    copy_cells(s, inside, kept);
    if (kept.cells() == 0) t.fail("x_range", "no cell's centroid lies in it");
    kept.reindex();
    kept.step = s.step;
    kept.time = s.time;
    s = std::move(kept);
  }
  if (scene.auto_box) fit_box(scene, s);
  return s;
}

}  // namespace semlb::engine
