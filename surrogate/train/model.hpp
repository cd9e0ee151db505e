// The trainable controller: torch GRUCell (same gate layout as controllers/gru.hpp) + zero-initialised head.
#pragma once
#include <torch/torch.h>

#include "controllers/gru.hpp"

namespace semlb::train {

struct ControllerImpl : torch::nn::Module {
  ControllerImpl(long inputs, long hidden);
  // One event for N boundaries: returns (new hidden [N,H], residual [N]).
  std::pair<torch::Tensor, torch::Tensor> step(const torch::Tensor& x, const torch::Tensor& h);

  torch::nn::GRUCell cell{nullptr};
  torch::nn::Linear head{nullptr};
  long hidden;
};
TORCH_MODULE(Controller);

// Copies the weights into the controllers' format (float -> double, exact).
GruWeights export_weights(Controller& model, double ds_max_frac, FeatureSet features = FeatureSet::v1);

// Parity record: residuals of `model` (as trained, float32) for a fixed input sequence [T, B, F].
struct Parity {
  std::vector<long> shape;        // T, B, F
  std::vector<double> inputs;     // T*B*F, row-major
  std::vector<double> residuals;  // T*B
};
Parity record_parity(Controller& model, long events, long boundaries, uint64_t seed);

}  // namespace semlb::train
