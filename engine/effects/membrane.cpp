// "membrane": the basement membrane at z = 0 (V_ext): a repulsive wall for every element and
// adhesion for basal elements.
#include "../effect.hpp"

namespace semlb::engine {
namespace {

class Membrane final : public Effect {
 public:
  explicit Membrane(const Section& s)
      : params_{s.real("wall_U", 2.0, 0, 1e9), s.real("wall_xi", 0.5, 1e-9, 1e9), s.real("adhesion_V", 1.0, 0, 1e9),
                s.real("adhesion_xi", 2.0, 1e-9, 1e9)} {}
  std::string name() const override { return "membrane"; }
  bool adds_forces() const override { return true; }
  void forces(Backend& b, const Grid&) override { b.membrane_forces(params_); }

 private:
  std::vector<double> params_;
};

const EffectRegistrar registrar("membrane", {20, [](const Section& s, const Scene&) { return std::make_unique<Membrane>(s); }});

}  // namespace
}  // namespace semlb::engine
