// "mechanics": intra- and inter-cell Morse interactions (eq. 1, V_ele) as a pair term, inter-cell sets per type pair
// (evaluator: mechanics.h; docs/engine.md "Physics as implemented").
#include "pair_term.hpp"

#include "effects/cell_types.hpp"

#define SEMLB_PAIR_HEADER "pairs/mechanics.h"
#define SEMLB_PAIR_NAME mechanics
#include "pairs/instantiate.hpp"

namespace semlb::engine {
namespace {

struct Morse {
  double U0, V0, xi1, xi2;
};

Morse read_morse(const Section& s, const Morse& fallback) {
  Morse m{s.real("U0", fallback.U0, 0, 1e9), s.real("V0", fallback.V0, 0, 1e9), s.real("xi1", fallback.xi1, 1e-9, 1e9),
          s.real("xi2", fallback.xi2, 1e-9, 1e9)};
  s.finish();
  return m;
}

// effects.mechanics: {intra: {U0: 4, V0: 1, xi1: 0.8, xi2: 1.1}, inter: {U0: 4, V0: 0.5, xi1: 0.8, xi2: 1.1},
// pairs: {TYPE-TYPE: {...}}}: the derived table of mechanics.h.
std::vector<double> read(const Section& s, double /*cutoff*/) {
  std::vector<double> table(SEMLB_MORSE_TABLE_SIZE);
  const auto put = [&](int at, const Morse& m) {  // derived constants: see mechanics.h
    table[at] = m.U0 / m.xi1;
    table[at + 1] = 1 / m.xi1;
    table[at + 2] = m.V0 / m.xi2;
    table[at + 3] = 1 / m.xi2;
  };
  const Morse intra = read_morse(s.child("intra"), {4.0, 1.0, 0.8, 1.1});
  const Morse inter = read_morse(s.child("inter"), {4.0, 0.5, 0.8, 1.1});
  put(SEMLB_MORSE_INTRA, intra);
  for (int a = 0; a < kCellTypes; ++a)
    for (int b = 0; b < kCellTypes; ++b) put(SEMLB_MORSE_INTER(a, b), inter);
  // Selective adhesion: `pairs: {spinous-spinous: {V0: 0.7}}` overrides the inter set (symmetric).
  const Section pairs = s.child("pairs");
  for (const auto& key : pairs.keys()) {
    const auto dash = key.find('-');
    const int a = type_from_name(key.substr(0, dash)),
              b = dash == std::string::npos ? -1 : type_from_name(key.substr(dash + 1));
    if (a < 0 || b < 0) pairs.fail(key, "expected TYPE-TYPE with types basal, spinous, granular");
    const Morse m = read_morse(pairs.child(key), inter);
    put(SEMLB_MORSE_INTER(a, b), m);
    put(SEMLB_MORSE_INTER(b, a), m);
  }
  pairs.finish();
  return table;
}

static_assert(SEMLB_MORSE_TYPES == kCellTypes, "mechanics.h's table holds one inter set per pair of cell types");

const Registrar<PairTerm> registrar("mechanics", {10, read, phys64::mechanics::pair, phys32::mechanics::pair,
                                                  "{intra: {V0: 1.2}, pairs: {basal-spinous: {V0: 0.3}}}"});

}  // namespace
}  // namespace semlb::engine
