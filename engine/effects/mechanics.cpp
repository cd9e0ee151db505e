// "mechanics": intra- and inter-cell Morse interactions (eq. 1, V_ele), inter-cell sets per type pair.
#include "backends/cpu_physics.hpp"
#include "effect.hpp"

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

class Mechanics final : public Effect {
 public:
  Mechanics(const Section& s, const Scene& scene) : cutoff_(scene.cutoff), table_(SEMLB_TABLE_SIZE) {
    const Morse intra = read_morse(s.child("intra"), {4.0, 1.0, 0.8, 1.1});
    const Morse inter = read_morse(s.child("inter"), {4.0, 0.5, 0.8, 1.1});
    put(SEMLB_MORSE_INTRA, intra);
    for (int a = 0; a < kCellTypes; ++a)
      for (int b = 0; b < kCellTypes; ++b) put(SEMLB_MORSE_INTER(a, b), inter);
    // Selective adhesion: `pairs: {spinous-spinous: {V0: 0.7}}` overrides the inter set (symmetric).
    const Section pairs = s.child("pairs");
    for (const auto& key : pairs.keys()) {
      const auto dash = key.find('-');
      const int a = type_from_name(key.substr(0, dash)), b = dash == std::string::npos ? -1 : type_from_name(key.substr(dash + 1));
      if (a < 0 || b < 0) pairs.fail(key, "expected TYPE-TYPE with types basal, spinous, granular");
      const Morse m = read_morse(pairs.child(key), inter);
      put(SEMLB_MORSE_INTER(a, b), m);
      put(SEMLB_MORSE_INTER(b, a), m);
    }
    pairs.finish();
  }
  std::string name() const override { return "mechanics"; }
  bool adds_forces() const override { return true; }
  void forces(Backend& b, const Grid& g) override { b.pair_forces_local(table_, cutoff_, g); }
  void nonlocal_forces(Backend& b, const Grid& g) override { b.pair_forces_nonlocal(table_, cutoff_, g); }

 private:
  void put(int at, const Morse& m) {  // derived constants: see evaluator.h
    table_[at] = m.U0 / m.xi1;
    table_[at + 1] = 1 / m.xi1;
    table_[at + 2] = m.V0 / m.xi2;
    table_[at + 3] = 1 / m.xi2;
  }
  double cutoff_;
  std::vector<double> table_;
};

const EffectRegistrar registrar("mechanics", {10, [](const Section& s, const Scene& scene) {
                                                return std::make_unique<Mechanics>(s, scene);
                                              }});

}  // namespace
}  // namespace semlb::engine
