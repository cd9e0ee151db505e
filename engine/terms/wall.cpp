// "wall": lateral confinement walls at xlo/xhi/ylo/yhi as an element term (evaluator: wall.h; docs/engine.md "Physics as implemented").
#include "term.hpp"

#include "common/text_io.hpp"

#define SEMLB_TERM_HEADER "terms/wall.h"
#include "terms/instantiate.hpp"

namespace semlb::engine {
namespace {

constexpr double kAbsent = 1e30;  // where an absent face sits (wall.h)

// effects.wall: {xlo, xhi, ylo, yhi: um, at least one; wall_U: 2, wall_xi: 0.5, adhesion_V: 0, adhesion_xi: 2}.
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

const ElementTermRegistrar registrar("wall", {25, read, phys64::semlb_term_wall, phys32::semlb_term_wall,
                                                    "{xlo: -20, xhi: 400, ylo: -20, yhi: 400, adhesion_V: 0.5, adhesion_xi: 20}"});

}  // namespace
}  // namespace semlb::engine
