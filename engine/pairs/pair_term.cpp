// The pair-term registry, and each term as an effect that adds the pair forces through
// ForceKernels::pair_forces_local/nonlocal.
#include "pair_term.hpp"

#include "common/errors.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// A pair term listed in the scene: its parameters read once; each step the local part (owned on owned) while the
// ghosts travel, the non-local part (ghosts on owned) after they arrived.
class PairTermEffect final : public Effect {
 public:
  PairTermEffect(const std::string& name, const Section& s, const Scene& scene)
      : forces_(pair_forces_of(name,
                               checked_plugin_params(PairTerm::kKind, name, PairTerms::at(name).read(s, scene.cutoff)),
                               scene.cutoff)) {
    for (const auto& [other, section] : scene.effects) {  // the later-listed term is the one refused
      if (other == name) break;
      if (PairTerms::find(other))
        throw InputError(s.where("") + "a scene lists one pair term, and '" + other + "' is listed already");
    }
  }
  std::string name() const override { return forces_.term; }
  bool adds_forces() const override { return true; }
  void forces(ForceKernels& b, const Grid& g) override { b.pair_forces_local(forces_, g); }
  void nonlocal_forces(ForceKernels& b, const Grid& g) override { b.pair_forces_nonlocal(forces_, g); }

 private:
  PairForces forces_;
};

}  // namespace

void PairTerm::registering(const std::string& name, const PairTerm& term) {
  register_plugin_effect(PairTerm::kKind, name, term, [name](const Section& s, const Scene& scene) {
    return std::make_unique<PairTermEffect>(name, s, scene);
  });
}

PairForces pair_forces_of(const std::string& term, std::vector<double> params, double cutoff) {
  const PairTerm& t = PairTerms::at(term);
  return {term, std::move(params), cutoff, t.f64, t.f32};
}

std::string scene_pair_term(const Scene& scene) {
  for (const auto& [name, section] : scene.effects)
    if (PairTerms::find(name)) return name;
  return "";
}

}  // namespace semlb::engine
