// The registry of per-cell fields (cell_fields.hpp).
#include "cell_fields.hpp"

#include <stdexcept>

namespace semlb::engine {

void CellFieldInfo::registering(const std::string& name, const CellFieldInfo& info) {
  if (info.effect.empty() || name.rfind(info.effect + ".", 0) != 0 || name.size() == info.effect.size() + 1)
    throw std::logic_error("cell field '" + name + "': the name must be '" + info.effect +
                           ".NAME' (its effect, a dot, a name)");
}

void declare_cell_fields(State& s, const std::vector<std::string>& effects) {
  for (const auto& name : CellFields::names()) {
    const CellFieldInfo& info = CellFields::at(name);
    for (const auto& e : effects)
      if (e == info.effect && !s.cell_fields.count(name)) s.cell_fields[name].assign(s.cell_id.size(), info.initial);
  }
  for (const auto& [name, f] : s.cell_fields)
    if (f.size() != s.cell_id.size())
      throw std::logic_error("cell field '" + name + "' holds " + std::to_string(f.size()) + " values for " +
                             std::to_string(s.cell_id.size()) + " cells");
}

int cell_field_index(const State& s, const std::string& name) {
  int k = 0;
  for (const auto& [n, f] : s.cell_fields) {
    if (n == name) return k;
    ++k;
  }
  return -1;
}

}  // namespace semlb::engine
