// "relu": ya||a's piecewise-linear pair force as a pair term (evaluator: relu.h; docs/engine.md "Physics as
// implemented").
#include "pair_term.hpp"

#include "common/text_io.hpp"

#define SEMLB_PAIR_HEADER "pairs/relu.h"
#define SEMLB_PAIR_NAME relu
#include "pairs/instantiate.hpp"

namespace semlb::engine {
namespace {

// One set {k_rep, k_adh (force units per um), r0 (um, the equilibrium distance), r_max (um, where the force lets
// go)}: r0 < r_max <= the scene's cutoff, since a pair beyond the cutoff is never seen.
void read_set(const Section& s, double cutoff, const std::vector<double>& fallback, std::vector<double>& p) {
  // k_rep > 0: coincident elements are pushed apart by f(0) = k_rep r0
  const double k_rep = s.real("k_rep", fallback[0], 0, 1e9, true), k_adh = s.real("k_adh", fallback[1], 0, 1e9);
  const double r0 = s.real("r0", fallback[2], 0, 1e9, true), r_max = s.real("r_max", fallback[3], 0, 1e9, true);
  if (!(r0 < r_max))
    s.fail(s.has("r_max") ? "r_max" : "r0",
           "r0 (" + format_real(r0) + " um) must be below r_max (" + format_real(r_max) + " um)");
  if (r_max > cutoff)
    s.fail("r_max", format_real(r_max) + " um" + (s.has("r_max") ? "" : " (the default)") +
                        " is beyond the scene's cutoff (" + format_real(cutoff) +
                        " um): pairs beyond the cutoff are never seen; raise `cutoff` or lower r_max");
  s.finish();
  p.insert(p.end(), {k_rep, k_adh, r0, r_max});
}

// effects.relu: {intra: {k_rep: 1, k_adh: 0.5, r0: 5, r_max: 7}, inter: {k_rep: 1, k_adh: 0.25, r0: 5, r_max: 7}}
// (r_max at most the cutoff). Defaults: r0 = 5 um, the equilibrium distance of mechanics' default intra set
// (U0/xi1 e^{-r/xi1} = V0/xi2 e^{-r/xi2} at r = 5.0 um), so the two laws give tissues of one density.
std::vector<double> read(const Section& s, double cutoff) {
  std::vector<double> p;
  read_set(s.child("intra"), cutoff, {1.0, 0.5, 5.0, 7.0}, p);
  read_set(s.child("inter"), cutoff, {1.0, 0.25, 5.0, 7.0}, p);
  return p;
}

const Registrar<PairTerm> registrar("relu", {10, read, phys64::relu::pair, phys32::relu::pair,
                                             "{intra: {k_rep: 2, k_adh: 0.5, r0: 4, r_max: 6}, inter: {k_adh: 0.1}}"});

}  // namespace
}  // namespace semlb::engine
