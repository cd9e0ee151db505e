// "clock": one element per cycle_time / (max_elements - min_elements) h (10 -> 20 elements per cycle by default), for
// cells of the listed types; with `front: {x0, speed}` only behind a proliferative front (evaluator: clock.h).
#include "growth_law.hpp"

#include "physics/cpu_physics.hpp"
#include "effects/cell_fields.hpp"
#include "effects/cell_types.hpp"

namespace semlb::engine::cellrules {
#include "growth/clock.h"
}  // namespace semlb::engine::cellrules

namespace semlb::engine {
namespace {

// (period, type mask, max_elements, front, x0, speed, cycle_time): clock.h's parameters, then the cycle.
std::vector<double> read(const Section& s) {
  const double cycle = s.real("cycle_time", 20.0, 1e-9, 1e12);
  const long min = s.integer("min_elements", 10, 1, kMaxSlots - 1),
             max = s.integer("max_elements", 20, 1, kMaxSlots - 1);
  if (max <= min) s.fail("max_elements", "must exceed min_elements");
  const int types = type_mask(read_types(s, "types", {"basal"}));
  double front = 0, x0 = 0, speed = 0;
  if (s.has("front")) {  // the proliferative wave: both keys required, nothing else
    const Section f = s.child("front");
    for (const char* k : {"x0", "speed"})
      if (!f.has(k)) f.fail(k, "missing (front: {x0: um, speed: um/h})");
    front = 1;
    x0 = f.real("x0", 0.0, -1e12, 1e12);
    speed = f.real("speed", 0.0, -1e12, 1e12);
    f.finish();
  }
  return {cycle / static_cast<double>(max - min),
          static_cast<double>(types),
          static_cast<double>(max),
          front,
          x0,
          speed,
          cycle};
}

const Registrar<CellFieldInfo> clock("growth.clock",
                                     {"growth", 0.0,
                                      "h since the cell last added an element (starts at a random phase)"});
const Registrar<GrowthLaw> registrar("clock", {read, cellrules::semlb_growth_clock, "growth.clock",
                                               [](const std::vector<double>& p, double u) { return p[0] * u; },
                                               [](const std::vector<double>& p) { return p[6]; },
                                               "{law: clock, cycle_time: 2}"});

}  // namespace
}  // namespace semlb::engine
