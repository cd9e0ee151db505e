// The effect registry.
#include "effect.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "common/errors.hpp"

namespace semlb::engine {

void EffectInfo::registering(const std::string& name, const EffectInfo&) {
  // An effect's phase column NAME_s in run.csv must not be one of the driver's own (run_header: wall_s, and the
  // integrate_s and cells_s phases). A name registered twice: Registry::add.
  if (name == "wall" || name == "integrate" || name == "cells")
    throw std::logic_error("effect '" + name + "': the name is taken (run.csv has a column " + name + "_s of its own)");
}

std::vector<std::unique_ptr<Effect>> make_effects(const Scene& scene) {
  std::vector<std::pair<int, std::unique_ptr<Effect>>> made;
  for (const auto& [name, section] : scene.effects) {
    const EffectInfo* info = Effects::find(name);
    if (!info) section.fail("", "effect '" + name + "' is unknown (known: " + Effects::known() + ")");
    made.emplace_back(info->order, info->make(section, scene));
    section.finish();
  }
  std::stable_sort(made.begin(), made.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::unique_ptr<Effect>> out;
  for (auto& [o, e] : made) out.push_back(std::move(e));
  return out;
}

CellRules cell_rules_of(const std::vector<std::unique_ptr<Effect>>& effects, const State& s, bool single) {
  CellRules r{};
  r.fields = static_cast<int>(s.cell_fields.size());
  r.growth = r.division = r.growth_field = r.depth_field = -1;
  for (const auto& e : effects)
    if (e->changes_cells()) e->cell_rules(r, s);
  r.single = single ? 1 : 0;
  return r;
}

}  // namespace semlb::engine
