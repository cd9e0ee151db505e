// "noise": Brownian displacement sqrt(2 D dt) N(0,1) per coordinate, keyed by (seed, element key, step).
#include <cmath>

#include "effect.hpp"

namespace semlb::engine {
namespace {

constexpr uint64_t kNoiseStream = 0x6e6f697365ULL;  // separates the noise stream from growth draws

class Noise final : public Effect {
 public:
  Noise(const Section& s, const Scene& scene)
      : amplitude_(std::sqrt(2 * s.real("diffusion", 0.01, 0, 1e9) * scene.dt)), seed_(scene.seed ^ kNoiseStream) {}
  std::string name() const override { return "noise"; }
  bool moves_after_integration() const override { return true; }
  void after_integration(ForceKernels& b, long step) override { b.noise(amplitude_, seed_, step); }

 private:
  double amplitude_;
  uint64_t seed_;
};

const Registrar<EffectInfo> registrar("noise", {30, [](const Section& s, const Scene& scene) {
                                                  return std::make_unique<Noise>(s, scene);
                                                }});

}  // namespace
}  // namespace semlb::engine
