// "membrane": the basement membrane at z = 0 (V_ext): a repulsive wall for every element and
// adhesion for basal elements.
#include "effect.hpp"

namespace semlb::engine {
namespace {

class Membrane final : public Effect {
 public:
  explicit Membrane(const Section& s) {
    const double U = s.real("wall_U", 2.0, 0, 1e9), xi_w = s.real("wall_xi", 0.5, 1e-9, 1e9);
    const double V = s.real("adhesion_V", 1.0, 0, 1e9), xi_a = s.real("adhesion_xi", 2.0, 1e-9, 1e9);
    params_ = {U / xi_w, 1 / xi_w, V / xi_a, 1 / xi_a};  // derived constants: see evaluator.h
  }
  std::string name() const override { return "membrane"; }
  bool adds_forces() const override { return true; }
  void forces(Backend& b, const Grid&) override { b.membrane_forces(params_); }

 private:
  std::vector<double> params_;
};

const EffectRegistrar registrar("membrane", {20, [](const Section& s, const Scene&) { return std::make_unique<Membrane>(s); }});

}  // namespace
}  // namespace semlb::engine
