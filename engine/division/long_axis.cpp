// "long_axis": the size trigger, and the split plane normal to the gyration tensor's long axis (evaluator:
// long_axis.h); the division rule a scene gets when it names none.
#include "division_rule.hpp"

#include "physics/cpu_physics.hpp"

namespace semlb::engine::cellrules {
#include "division/long_axis.h"
}  // namespace semlb::engine::cellrules

namespace semlb::engine {
namespace {

const Registrar<DivisionRule> registrar("long_axis", {read_size_trigger, cellrules::semlb_divides_long_axis,
                                                      cellrules::semlb_division_axis_long_axis,
                                                      "{rule: long_axis, at_elements: 14}"});

}  // namespace
}  // namespace semlb::engine
