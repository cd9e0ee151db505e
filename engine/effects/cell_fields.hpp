// Per-cell fields as effects declare them: a registry of named doubles per cell (owner effect, initial value),
// the set a run carries (the State's cell_fields, in name order) and a field's index in that set.
#pragma once
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "model/state.hpp"

namespace semlb::engine {

// One per-cell field: a double per cell that the owning effect's cell rule reads and writes, carried by every
// backend (the OpenCL device's record), the migration and the ghosts' wire format, the state files and checkpoints.
struct CellFieldInfo {
  static constexpr const char* kKind = "cell field";
  static constexpr const char* kListed = "cell-fields";
  std::string effect;   // the effect that declares it: the field exists in a run that lists this effect
  double initial = 0;   // the value of a cell that has none (a generated tissue, a file without the dataset)
  std::string meaning;  // one line with the unit, for `semlb list` and error messages

  // A field is registered as `name` = "EFFECT.what" (e.g. "growth.clock") of effect info.effect: std::logic_error
  // when the name does not start with "EFFECT.".
  static void registering(const std::string& name, const CellFieldInfo& info);
};
using CellFields = PluginKind<CellFieldInfo>;

// Adds to `s` each field that an effect in `effects` declares and `s` lacks, one `initial` per cell; a field
// `s` has already (a restart, an effect's own prepare()) is kept. std::logic_error when a field `s` has holds
// other than one value per cell.
void declare_cell_fields(State& s, const std::vector<std::string>& effects);

// The index of field `name` in the record of `s`'s fields (cell_fields in name order: the order every backend
// stores a cell's fields in), or -1 when `s` has no such field.
int cell_field_index(const State& s, const std::string& name);

}  // namespace semlb::engine
