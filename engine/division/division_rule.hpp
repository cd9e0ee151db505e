// Division rules: whether a cell divides at a cell stage and the normal of its split plane (the division effect,
// `effects.division: {rule: NAME, ...}`), each written once as a C99 evaluator header (division/NAME.h) and registered
// by name. The split itself (the gyration tensor, the halves on either side of the plane through the centroid, the
// daughter's id from division.depth, state.hpp) is the core's (physics/cells.h), run on the host by the C++ backends
// and by the OpenCL kernel cells_plan, which calls the scene's rule by its index.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "model/scene.hpp"

namespace semlb::engine {

// Whether a cell of `type` with `count` elements after growth and centroid[3] (um, before growth) divides now; `p` the
// rule's derived parameters (DivisionRule::read). `semlb_divides_NAME` of division/NAME.h.
using DivisionTrigger = int (*)(int type, int count, const double* centroid, const double* p);
// The unit normal axis[3] of the split plane of a dividing cell from its gyration tensor g[6] = (g00, g01, g02, g11,
// g12, g22) (um^2) and centroid[3] (um), both after growth. `semlb_division_axis_NAME` of division/NAME.h.
using DivisionAxis = void (*)(const double* g, const double* centroid, const double* p, double* axis);

// A registered division rule. Its name is the value of `effects.division.rule`, the stem of its header
// division/NAME.h; the OpenCL kernels call it by its index in DivisionRules::names() (the generated dispatches
// semlb_divides and semlb_division_axis, in name order too). division/NAME.cpp includes division/NAME.h inside
// namespace cellrules (cpu_physics.hpp) and registers the rule.
struct DivisionRule {
  static constexpr const char* kKind = "division rule";
  static constexpr const char* kListed = "division-rules";
  // The derived parameters (at most SEMLB_CELL_RULE_PARAMS doubles) from the division section, whose `rule` key is
  // the effect's; its errors name file, line and field.
  std::function<std::vector<double>(const Section&)> read;
  DivisionTrigger divides = nullptr;
  DivisionAxis axis = nullptr;
  // A valid division section for it (YAML flow map, `rule` included): what the suites that iterate
  // DivisionRules::names() run it with.
  std::string example = "{}";

  // std::logic_error unless `name` is a C identifier.
  static void registering(const std::string& name, const DivisionRule&) { check_plugin_name(kKind, name); }
};
using DivisionRules = PluginKind<DivisionRule>;

// The size trigger the shipped rules share (cells.h semlb_cell_divides_by_size): (type mask, at_elements) from the
// section's `types` (default [basal]) and `at_elements` (default 20, in [2, kMaxSlots - 1]).
std::vector<double> read_size_trigger(const Section& s);

}  // namespace semlb::engine
