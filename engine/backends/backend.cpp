// Backend registry and the bin grid shared by every binned backend.
#include "backend.hpp"

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"
#include "common/registry.hpp"

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

}  // namespace semlb::engine
