// "desquamation": cells whose centroid rises above `height` um are shed (evaluator: desquamation.h).
#include "removal.hpp"

#include "physics/cpu_physics.hpp"

namespace semlb::engine::cellrules {
#include "removal/desquamation.h"
}  // namespace semlb::engine::cellrules

namespace semlb::engine {
namespace {

// effects.desquamation: {height: um above the membrane at z = 0; required}.
std::vector<double> read(const Section& s) {
  if (!s.has("height")) {  // a misspelt key is the likelier cause: named first
    for (const auto& k : s.keys()) s.fail(k, "unknown setting (known: height)");
    s.fail("height", "is required (um: cells whose centroid is above it are shed)");
  }
  return {s.real("height", 0, 0, 1e9)};
}

const Registrar<RemovalRule> registrar("desquamation",
                                       {70, read, cellrules::semlb_remove_desquamation, "{height: 12}"});

}  // namespace
}  // namespace semlb::engine
