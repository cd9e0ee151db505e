// Differentiable rollout of a batch of episodes (paper Sec. IV-E): hard decisions in the forward pass
// (straight-through rounding, the reactive sweep), soft slice assignment with a temperature for gradients.
#pragma once
#include <torch/torch.h>

#include <vector>

#include "config.hpp"
#include "episodes.hpp"
#include "model.hpp"

namespace semlb::train {

struct SoftStats {
  double imbalance = 0;  // mean (max-mean)/mean of the soft times over episodes and events
  double migration = 0;  // mean slices moved per episode
};

// Loss = mean over episodes of [ mean_t ((max-mean)/mean + w_s std/mean) / scale + λ m Σ_t Σ_b |Δb| ],
// over the intervals t = 1..events that the controller's decisions govern; scale and m per
// imbalance_norm / migration_norm (config.hpp).
torch::Tensor soft_rollout_loss(Controller& model, const std::vector<Episode>& episodes, const TrainConfig& c,
                                double temperature, SoftStats* stats = nullptr);

// Rank times of integer boundaries under a temperature-softened slice assignment: slice s belongs to the
// left of boundary x with weight sigmoid((x - s - 0.5) / temperature). Exposed for tests.
torch::Tensor soft_rank_times(const std::vector<double>& work, const torch::Tensor& boundaries, double temperature);

}  // namespace semlb::train
