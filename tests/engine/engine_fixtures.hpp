// Helpers for the engine tests: small scenes from text, random tissues and backend lists.
#pragma once
#include <random>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "engine/backends/backend.hpp"
#include "engine/backends/opencl.hpp"
#include "engine/model/scene.hpp"
#include "engine/model/state.hpp"

namespace semlb::engine::testing {

// A scene from YAML text; effects default to mechanics only.
inline Scene scene_from(const std::string& yaml, const std::vector<std::string>& overrides = {}) {
  return parse_scene(yaml, "test.yaml", overrides);
}

inline const char* kMechanicsYaml = R"(
name: t
cutoff: 8.75
tissue: {cells: 40, layers: 2}
time: {dt: 0.01, steps: 20}
backend: {name: serial}
effects:
  mechanics: {}
)";

// Cells of `per_cell` elements scattered uniformly in a box (types cycle through the three).
inline State random_state(long cells, int per_cell, double side, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, side);
  State s;
  for (long c = 0; c < cells; ++c) {
    s.cell_id.push_back(static_cast<uint64_t>(c) * 7 + 3);
    s.cell_type.push_back(static_cast<int>(c % 3));
    s.cell_count.push_back(per_cell);
    for (int e = 0; e < 3 * per_cell; ++e) s.position.push_back(u(rng));
  }
  s.reindex();
  return s;
}

// Backends this machine can run: the C++ ones always, the OpenCL ones when a platform exists.
inline std::vector<std::string> available_backends() {
  std::vector<std::string> b = {"serial", "cpu-binned"};
  if (!cl::list_devices().empty()) {
    b.push_back("opencl-allpairs");
    b.push_back("opencl-binned");
  }
  return b;
}

}  // namespace semlb::engine::testing
