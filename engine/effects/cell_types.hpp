// Parsing of a cell-type list setting shared by the cell effects ("types: [basal]").
#pragma once
#include <array>

#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

inline std::array<bool, kCellTypes> read_types(const Section& s, const std::string& key,
                                               const std::vector<std::string>& fallback) {
  std::array<bool, kCellTypes> on{};
  for (const auto& name : s.texts(key, fallback)) {
    const int t = type_from_name(name);
    if (t < 0) s.fail(key, "'" + name + "' is not a cell type (basal, spinous, granular)");
    on[t] = true;
  }
  return on;
}

// The types as a bit mask (bit t: type t), the form of CellRules.
inline int type_mask(const std::array<bool, kCellTypes>& on) {
  int mask = 0;
  for (int t = 0; t < kCellTypes; ++t) mask |= on[t] ? 1 << t : 0;
  return mask;
}

}  // namespace semlb::engine
