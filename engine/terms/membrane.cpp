// "membrane": the basement membrane at z = 0 as an element term (evaluator: membrane.h).
#include "term.hpp"

#define SEMLB_TERM_HEADER "terms/membrane.h"
#include "terms/instantiate.hpp"

namespace semlb::engine {
namespace {

std::vector<double> read(const Section& s) {
  const double U = s.real("wall_U", 2.0, 0, 1e9), xi_w = s.real("wall_xi", 0.5, 1e-9, 1e9);
  const double V = s.real("adhesion_V", 1.0, 0, 1e9), xi_a = s.real("adhesion_xi", 2.0, 1e-9, 1e9);
  return {U / xi_w, 1 / xi_w, V / xi_a, 1 / xi_a};
}

const Registrar<ElementTerm> registrar("membrane", {20, read, phys64::semlb_term_membrane, phys32::semlb_term_membrane,
                                                    "{}", nullptr});  // no initial-state check

}  // namespace
}  // namespace semlb::engine
