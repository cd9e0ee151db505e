// Torch controller and its export to the Eigen GRU's format, with recorded parity vectors.
#include "model.hpp"

#include "controllers/features.hpp"
#include "surrogate/rng.hpp"

namespace semlb::train {

ControllerImpl::ControllerImpl(long inputs, long h) : hidden(h) {
  cell = register_module("cell", torch::nn::GRUCell(torch::nn::GRUCellOptions(inputs, h)));
  head = register_module("head", torch::nn::Linear(h, 1));
  torch::NoGradGuard no_grad;
  head->weight.zero_();
  head->bias.zero_();
}

std::pair<torch::Tensor, torch::Tensor> ControllerImpl::step(const torch::Tensor& x, const torch::Tensor& h) {
  auto next = cell(x, h);
  return {next, head(next).squeeze(1)};
}

namespace {
Eigen::MatrixXd to_eigen(const torch::Tensor& t) {
  const auto d = t.detach().to(torch::kDouble).contiguous();
  const long rows = d.size(0), cols = d.dim() > 1 ? d.size(1) : 1;
  Eigen::MatrixXd m(rows, cols);
  const auto matrix = d.reshape({rows, cols});
  auto a = matrix.accessor<double, 2>();
  for (long i = 0; i < rows; ++i)
    for (long j = 0; j < cols; ++j) m(i, j) = a[i][j];
  return m;
}
}  // namespace

GruWeights export_weights(Controller& model, double ds_max_frac, FeatureSet features) {
  GruWeights w;
  w.features = features;
  w.hidden = static_cast<int>(model->hidden);
  w.inputs = kFeatureCount;
  w.ds_max_frac = ds_max_frac;
  w.w_ih = to_eigen(model->cell->weight_ih);
  w.w_hh = to_eigen(model->cell->weight_hh);
  w.b_ih = to_eigen(model->cell->bias_ih);
  w.b_hh = to_eigen(model->cell->bias_hh);
  w.head_w = to_eigen(model->head->weight).transpose();
  w.head_b = model->head->bias.item<double>();
  return w;
}

Parity record_parity(Controller& model, long events, long boundaries, uint64_t seed) {
  Parity p;
  p.shape = {events, boundaries, kFeatureCount};
  torch::NoGradGuard no_grad;
  auto h = torch::zeros({boundaries, model->hidden});
  for (long t = 0; t < events; ++t) {
    auto x = torch::empty({boundaries, kFeatureCount});
    for (long b = 0; b < boundaries; ++b)
      for (long f = 0; f < kFeatureCount; ++f) {
        const double v = rng::uniform(-1.0, 1.0, seed, t, b, f);
        x[b][f] = static_cast<float>(v);
        p.inputs.push_back(static_cast<float>(v));  // the float the model actually saw
      }
    auto [next, r] = model->step(x, h);
    h = next;
    for (long b = 0; b < boundaries; ++b) p.residuals.push_back(r[b].item<double>());
  }
  return p;
}

}  // namespace semlb::train
