// Reactive policy: move each boundary toward its slower neighbour by the paper's rule, then the sweep.
#include "reactive.hpp"

#include <cmath>

#include "partition.hpp"
#include "policy.hpp"

namespace semlb {

std::vector<BoundaryProposal> reactive_proposals(const Observation& obs, const ReactiveParams& p) {
  const auto w = widths(obs.boundaries, obs.slices);
  std::vector<BoundaryProposal> out(obs.boundaries.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const double t_minus = obs.times[i], t_plus = obs.times[i + 1];
    BoundaryProposal& b = out[i];
    const double sum = t_plus + t_minus;
    b.local_imbalance = sum > 0.0 ? (t_plus - t_minus) / (0.5 * sum) : 0.0;
    b.direction = t_plus > t_minus ? 1 : (t_plus < t_minus ? -1 : 0);
    b.n_slow = b.direction > 0 ? w[i + 1] : w[i];
    if (std::fabs(b.local_imbalance) > p.tau) {
      const double t_slow = std::fmax(t_plus, t_minus);  // > 0 whenever |I_t| > 0
      b.magnitude = p.alpha * b.n_slow * std::fabs(t_plus - t_minus) / (2.0 * t_slow);
    }
  }
  return out;
}

long integer_step(int direction, double magnitude) { return direction * std::lround(magnitude); }

namespace {

class ReactivePolicy final : public Policy {
 public:
  explicit ReactivePolicy(ReactiveParams p) : p_(p) {}
  std::vector<int> decide(const Observation& obs) override {
    const auto proposals = reactive_proposals(obs, p_);
    std::vector<long> moves;
    for (const auto& b : proposals) moves.push_back(integer_step(b.direction, b.magnitude));
    return apply_moves(obs.boundaries, moves, obs.slices, obs.min_width);
  }

 private:
  ReactiveParams p_;
};

const Registrar<PolicyInfo> reactive_registrar("reactive", {[](PolicyParams& params) {
                                                 ReactiveParams p;
                                                 p.tau = params.real("tau", p.tau, 0.0, kMaxThreshold);
                                                 p.alpha = params.real("alpha", p.alpha, 0.0, 2.0, true, true);
                                                 return std::make_unique<ReactivePolicy>(p);
                                               }});

}  // namespace
}  // namespace semlb
