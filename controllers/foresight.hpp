// Perfect foresight, offline: the boundaries of every interval chosen knowing all future work, minimising
// sum_t I_global(t) + lambda * slices moved (docs/controllers.md "foresight"). An analysis floor, not a policy.
#pragma once
#include <span>
#include <vector>

#include "policy.hpp"

namespace semlb {

struct ForesightPath {
  std::vector<std::vector<int>> boundaries;  // [K][P-1]: the partition in force during interval t
  std::vector<double> imbalance;             // [K]: I_global of interval t (rank_sums of work[t])
  long migration = 0;                        // sum over t >= 1 and boundaries of |b_t - b_{t-1}|
  double objective = 0;                      // sum_t imbalance[t] + lambda * migration
  bool exact = false;                        // true for P <= 2 (the DP is then over the whole state space)
};

// work: [K][S] true per-slice work of intervals 0..K-1 (finite, non-negative); initial: the P-1 boundaries of
// interval 0 (fixed: the decision for interval 0 was made before the run); lambda >= 0 per slice moved.
// P = 2: exact DP over boundary positions, each transition an O(S) L1 distance transform (O(K S) in all).
// P > 2: block coordinate descent, each block one boundary's whole trajectory solved exactly by the same DP
// with the others fixed, from two starts (never move; the per-interval optimal contiguous partition), until
// a sweep gains nothing: a feasible path, so its objective is an upper bound on the optimum.
// Throws InputError for an infeasible initial partition, ragged work or a negative/non-finite lambda.
ForesightPath foresight_path(const std::vector<std::vector<double>>& work, std::span<const int> initial, int min_width,
                             double lambda);

// The registered name `foresight` carries lambda (parameter `lambda`, default 0.001, in [0, 1e6]) to offline
// evaluators; decide() refuses (InputError): the policy needs the whole run in advance, which no online loop
// (engine, replay without --score) has. Its PolicyNeeds say true_work, so the engine refuses it at load time.
class ForesightPolicy final : public Policy {
 public:
  explicit ForesightPolicy(double lambda) : lambda_(lambda) {}
  std::vector<int> decide(const Observation& obs) override;
  double lambda() const { return lambda_; }

 private:
  double lambda_;
};

}  // namespace semlb
