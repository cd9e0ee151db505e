// "oriented": the size trigger, and a split plane normal to a fixed axis (evaluator: oriented.h).
#include "division_rule.hpp"

#include <cmath>

#include "physics/cpu_physics.hpp"
#include "common/text_io.hpp"

namespace semlb::engine::cellrules {
#include "division/oriented.h"
}  // namespace semlb::engine::cellrules

namespace semlb::engine {
namespace {

// effects.division: {rule: oriented, axis: [x, y, z] (default [0, 0, 1], normalised; not 0), types, at_elements}.
std::vector<double> read(const Section& s) {
  std::vector<double> p = read_size_trigger(s);
  const auto axis = s.texts("axis", {"0", "0", "1"});
  if (axis.size() != 3) s.fail("axis", "must be three numbers [x, y, z] (the split plane's normal)");
  double n[3], norm = 0;
  for (int d = 0; d < 3; ++d) {
    n[d] = parse_real(axis[d], s.where("axis"), -1e6, 1e6);
    norm += n[d] * n[d];
  }
  if (!(norm > 0)) s.fail("axis", "must not be the zero vector");
  for (double v : n) p.push_back(v / std::sqrt(norm));
  return p;
}

const Registrar<DivisionRule> registrar("oriented", {read, cellrules::semlb_divides_oriented,
                                                     cellrules::semlb_division_axis_oriented,
                                                     "{rule: oriented, axis: [0, 0, 1], at_elements: 14}"});

}  // namespace
}  // namespace semlb::engine
