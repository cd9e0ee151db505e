// "differentiation": basal -> spinous on height, spinous -> granular on age, as a fate rule (evaluator:
// differentiation.h). The type selects the adhesion set of the pair term.
#include "fate.hpp"

#include "physics/cpu_physics.hpp"
#include "effects/cell_fields.hpp"

namespace semlb::engine::cellrules {
#include "fates/differentiation.h"
}  // namespace semlb::engine::cellrules

namespace semlb::engine {
namespace {

// effects.differentiation: {basal_height: 8 um, granular_after: 40 h}.
std::vector<double> read(const Section& s) {
  return {s.real("basal_height", 8.0, 0, 1e9), s.real("granular_after", 40.0, 0, 1e12)};
}

const Registrar<CellFieldInfo> age("differentiation.age",
                                   {"differentiation", 0.0, "h since the cell's type last changed"});
const Registrar<FateRule> registrar("differentiation", {60, read, cellrules::semlb_fate_differentiation,
                                                        "differentiation.age", "{basal_height: 6}"});

}  // namespace
}  // namespace semlb::engine
