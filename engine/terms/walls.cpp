// "walls": lateral confinement walls at xlo/xhi/ylo/yhi as an element term (evaluator: walls.h; docs/engine.md "Physics
// as implemented").
#include "term.hpp"

#include <algorithm>
#include <cmath>

#include "common/text_io.hpp"

#define SEMLB_TERM_HEADER "terms/walls.h"
#include "terms/instantiate.hpp"

namespace semlb::engine {
namespace {

constexpr double kAbsent = 1e30;  // where an absent face sits (walls.h)

// effects.walls: {xlo, xhi, ylo, yhi: um, at least one; wall_U: 2, wall_xi: 0.5, adhesion_V: 0, adhesion_xi: 2}.
std::vector<double> read(const Section& s) {
  const double U = s.real("wall_U", 2.0, 0, 1e9), xi_w = s.real("wall_xi", 0.5, 1e-9, 1e9);
  const double V = s.real("adhesion_V", 0.0, 0, 1e9), xi_a = s.real("adhesion_xi", 2.0, 1e-9, 1e9);
  std::vector<double> p = {U / xi_w, 1 / xi_w, V / xi_a, 1 / xi_a};
  for (const char* axis : {"x", "y"}) {
    const std::string lo = std::string(axis) + "lo", hi = std::string(axis) + "hi";
    const double a = s.real(lo, -kAbsent, -1e9, 1e9), b = s.real(hi, kAbsent, -1e9, 1e9);
    if (s.has(lo) && s.has(hi) && !(a < b)) s.fail(hi, "must be above " + lo + " (" + format_real(a) + " um)");
    p.push_back(a);
    p.push_back(b);
  }
  if (!s.has("xlo") && !s.has("xhi") && !s.has("ylo") && !s.has("yhi"))
    s.fail("", "names no face: give at least one of xlo, xhi, ylo, yhi (um)");
  return p;
}

// Elements behind a face by more than wall_xi (1/p[1]) at the start: the wall would throw them back with the force
// clamp, which time.max_displacement then reports as a numerical failure that names neither the wall nor the cause.
std::string check(const State& s, const std::vector<double>& p) {
  const double slack = 1 / p[1];
  const char* faces[4] = {"xlo", "xhi", "ylo", "yhi"};
  for (int f = 0; f < 4; ++f) {
    const double at = p[4 + f];
    if (std::abs(at) >= kAbsent) continue;
    const int axis = f / 2;
    const double sign = f % 2 ? 1.0 : -1.0;  // behind xlo: x < xlo; behind xhi: x > xhi
    long behind = 0;
    double worst = at;
    for (long e = 0; e < s.elements(); ++e) {
      const double x = s.position[3 * e + axis];
      if (sign * (x - at) > slack) ++behind, worst = sign > 0 ? std::max(worst, x) : std::min(worst, x);
    }
    if (behind)
      return std::to_string(behind) + " of " + std::to_string(s.elements()) + " elements start behind the face " +
             faces[f] + " = " + format_real(at) + " um (" + (axis ? "y" : "x") + " " +
             (sign > 0 ? "up to " : "down to ") + format_real(worst) +
             " um, more than wall_xi inside the wall): walls confine a tissue that starts inside them";
  }
  return "";
}

const Registrar<ElementTerm> registrar("walls",
                                       {25, read, phys64::semlb_term_walls, phys32::semlb_term_walls,
                                        "{xlo: -20, xhi: 400, ylo: -20, yhi: 400, adhesion_V: 0.5, adhesion_xi: 20}",
                                        check});

}  // namespace
}  // namespace semlb::engine
