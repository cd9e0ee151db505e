// Effect registry and the host-side helpers shared by cell effects.
#include "effect.hpp"

#include <algorithm>
#include <map>

#include "common/errors.hpp"
#include "common/registry.hpp"

namespace semlb::engine {
namespace {
Registry<EffectInfo>& registry() {
  static Registry<EffectInfo> r;
  return r;
}
}  // namespace

EffectRegistrar::EffectRegistrar(const std::string& name, EffectInfo info) { registry().add(name, std::move(info)); }

std::vector<std::string> effect_names() { return registry().names(); }

std::vector<std::unique_ptr<Effect>> make_effects(const Scene& scene) {
  std::vector<std::pair<int, std::unique_ptr<Effect>>> made;
  for (const auto& [name, section] : scene.effects) {
    const EffectInfo* info = registry().find(name);
    if (!info) section.fail("", "effect '" + name + "' is unknown (known: " + registry().known() + ")");
    made.emplace_back(info->order, info->make(section, scene));
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

Positions elements_of(const State& s, long cell) {
  Positions out(s.cell_count[cell]);
  for (size_t k = 0; k < out.size(); ++k)
    for (int d = 0; d < 3; ++d) out[k][d] = s.position[3 * (s.cell_first[cell] + k) + d];
  return out;
}

void copy_elements(const State& s, long cell, std::vector<double>& out) {
  const auto first = s.position.begin() + 3 * s.cell_first[cell];
  out.insert(out.end(), first, first + 3 * s.cell_count[cell]);
}

void rewrite_elements(State& s, const std::function<void(long, std::vector<double>&)>& emit, long added) {
  std::vector<double> out;
  out.reserve(s.position.size() + 3 * static_cast<size_t>(std::max(added, 0L)));
  std::vector<int> counts(s.cells());
  for (long c = 0; c < s.cells(); ++c) {
    const size_t before = out.size();
    emit(c, out);
    counts[c] = static_cast<int>((out.size() - before) / 3);
  }
  s.position.swap(out);
  s.cell_count.swap(counts);
  s.reindex();
}

}  // namespace semlb::engine
