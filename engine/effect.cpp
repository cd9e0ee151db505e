// Effect registry and the host-side helpers shared by cell effects.
#include "effect.hpp"

#include <algorithm>
#include <map>

#include "controllers/errors.hpp"

namespace semlb::engine {
namespace {
std::map<std::string, EffectInfo>& registry() {
  static std::map<std::string, EffectInfo> r;
  return r;
}
}  // namespace

EffectRegistrar::EffectRegistrar(const std::string& name, EffectInfo info) { registry()[name] = std::move(info); }

std::vector<std::string> effect_names() {
  std::vector<std::string> out;
  for (const auto& [n, i] : registry()) out.push_back(n);
  return out;
}

std::vector<std::unique_ptr<Effect>> make_effects(const Scene& scene) {
  std::vector<std::pair<int, std::unique_ptr<Effect>>> made;
  for (const auto& [name, section] : scene.effects) {
    const auto it = registry().find(name);
    if (it == registry().end()) {
      std::string known;
      for (const auto& n : effect_names()) known += (known.empty() ? "" : ", ") + n;
      section.fail("", "effect '" + name + "' is unknown (known: " + known + ")");
    }
    made.emplace_back(it->second.order, it->second.make(section, scene));
    section.finish();
  }
  std::stable_sort(made.begin(), made.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::unique_ptr<Effect>> out;
  for (auto& [o, e] : made) out.push_back(std::move(e));
  return out;
}

std::array<double, 3> centroid(const State& s, long cell) {
  std::array<double, 3> c{0, 0, 0};
  const long first = s.cell_first[cell];
  const int n = s.cell_count[cell];
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d) c[d] += s.position[3 * (first + k) + d];
  for (int d = 0; d < 3; ++d) c[d] /= std::max(n, 1);
  return c;
}

CellPositions cell_positions(const State& s) {
  CellPositions cells(s.cells());
  for (long c = 0; c < s.cells(); ++c)
    for (int k = 0; k < s.cell_count[c]; ++k) {
      const double* p = &s.position[3 * (s.cell_first[c] + k)];
      cells[c].push_back({p[0], p[1], p[2]});
    }
  return cells;
}

void rebuild(State& s, const CellPositions& cells) {
  s.position.clear();
  for (size_t c = 0; c < cells.size(); ++c) {
    s.cell_count[c] = static_cast<int>(cells[c].size());
    for (const auto& p : cells[c]) s.position.insert(s.position.end(), p.begin(), p.end());
  }
  s.reindex();
}

}  // namespace semlb::engine
