// GRU controller: Eigen inference, HDF5 weights (format v1), and the registered "gru" policy.
#include "gru.hpp"

#include <cmath>
#include <filesystem>
#include <random>

#include "common/errors.hpp"
#include "features.hpp"
#include "common/h5.hpp"
#include "partition.hpp"
#include "policy.hpp"
#include "reactive.hpp"

#ifndef SEMLB_DEFAULT_WEIGHTS
#define SEMLB_DEFAULT_WEIGHTS "controllers/weights/gru_default.h5"
#endif

namespace semlb {

GruWeights GruWeights::random_zero_head(int hidden, int inputs, uint64_t seed) {
  GruWeights w;
  w.hidden = hidden;
  w.inputs = inputs;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0 / std::sqrt(hidden), 1.0 / std::sqrt(hidden));
  auto fill = [&](auto& m) {
    for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  };
  w.w_ih.resize(3 * hidden, inputs);
  w.w_hh.resize(3 * hidden, hidden);
  w.b_ih.resize(3 * hidden);
  w.b_hh.resize(3 * hidden);
  fill(w.w_ih), fill(w.w_hh), fill(w.b_ih), fill(w.b_hh);
  w.head_w = Eigen::VectorXd::Zero(hidden);
  return w;
}

long GruWeights::parameter_count() const {
  return w_ih.size() + w_hh.size() + b_ih.size() + b_hh.size() + head_w.size() + 1;
}

Eigen::VectorXd gru_step(const GruWeights& w, const Eigen::VectorXd& x, const Eigen::VectorXd& h) {
  const int H = w.hidden;
  const Eigen::VectorXd gi = w.w_ih * x + w.b_ih;
  const Eigen::VectorXd gh = w.w_hh * h + w.b_hh;
  auto sigmoid = [](double v) { return 1.0 / (1.0 + std::exp(-v)); };
  const Eigen::VectorXd r = (gi.segment(0, H) + gh.segment(0, H)).unaryExpr(sigmoid);
  const Eigen::VectorXd z = (gi.segment(H, H) + gh.segment(H, H)).unaryExpr(sigmoid);
  const Eigen::VectorXd n =
      (gi.segment(2 * H, H) + r.cwiseProduct(gh.segment(2 * H, H))).unaryExpr([](double v) { return std::tanh(v); });
  return (Eigen::VectorXd::Ones(H) - z).cwiseProduct(n) + z.cwiseProduct(h);
}

double gru_head(const GruWeights& w, const Eigen::VectorXd& h) { return w.head_w.dot(h) + w.head_b; }

double residual_magnitude(double reactive_magnitude, double ds_max, double residual) {
  if (ds_max <= 0.0) return 0.0;
  if (residual == 0.0) return std::min(reactive_magnitude, ds_max);
  const double u = std::clamp(reactive_magnitude / ds_max, 0.0, 1.0 - 1e-6);
  return std::max(0.0, ds_max * std::tanh(std::atanh(u) + residual));
}

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::MatrixXd read_matrix(const h5::File& f, const std::string& name, hsize_t rows, hsize_t cols, bool vector) {
  std::vector<hsize_t> dims;
  const auto data = f.read(name, dims);
  const std::vector<hsize_t> want = vector ? std::vector<hsize_t>{rows} : std::vector<hsize_t>{rows, cols};
  if (dims != want) {
    auto shape = [](const std::vector<hsize_t>& d) {
      std::string s;
      for (auto v : d) s += (s.empty() ? "" : "x") + std::to_string(v);
      return s.empty() ? std::string("scalar") : s;
    };
    throw InputError(f.path() + ": dataset " + name + " has shape " + shape(dims) + ", expected " + shape(want));
  }
  for (size_t i = 0; i < data.size(); ++i)
    if (!std::isfinite(data[i]))
      throw InputError(f.path() + ": dataset " + name + " holds a non-finite value at index " + std::to_string(i));
  return Eigen::Map<const RowMajor>(data.data(), rows, vector ? 1 : cols);
}

void expect_text(const h5::File& f, const std::string& attr, const std::string& want) {
  const auto got = f.read_text_attr(attr);
  if (got != want)
    throw InputError(f.path() + ": attribute '" + attr + "' is '" + got + "', this build expects '" + want + "'");
}

}  // namespace

GruWeights load_gru_weights(const std::string& path) {
  const auto f = h5::File::open_read(path);
  expect_text(f, "format", "semlb-gru");
  if (const long v = f.read_int_attr("version"); v != kGruFormatVersion)
    throw InputError(path + ": attribute 'version' is " + std::to_string(v) + ", this build reads version " +
                     std::to_string(kGruFormatVersion));
  GruWeights w;
  w.features = parse_feature_set(f.read_text_attr("feature_set"), path + ": attribute 'feature_set': ");
  expect_text(f, "features", feature_list());
  w.hidden = static_cast<int>(f.read_int_attr("hidden"));
  w.inputs = kFeatureCount;
  w.ds_max_frac = f.read_real_attr("ds_max_frac");
  if (w.hidden < 1 || w.hidden > 4096)
    throw InputError(path + ": attribute 'hidden' = " + std::to_string(w.hidden) + " is out of range");
  if (!(w.ds_max_frac > 0.0 && w.ds_max_frac <= 1.0))
    throw InputError(path + ": attribute 'ds_max_frac' must be in (0, 1]");
  const hsize_t G = 3 * w.hidden, H = w.hidden, F = kFeatureCount;
  w.w_ih = read_matrix(f, "/gru/weight_ih", G, F, false);
  w.w_hh = read_matrix(f, "/gru/weight_hh", G, H, false);
  w.b_ih = read_matrix(f, "/gru/bias_ih", G, 1, true);
  w.b_hh = read_matrix(f, "/gru/bias_hh", G, 1, true);
  w.head_w = read_matrix(f, "/head/weight", 1, H, false).transpose();
  w.head_b = read_matrix(f, "/head/bias", 1, 1, true)(0, 0);
  return w;
}

void save_gru_weights(const std::string& path, const GruWeights& w, const std::function<void(h5::File&)>& extra) {
  h5::File::write_atomically(path, [&](h5::File& f) {
    f.write_attr("format", std::string("semlb-gru"));
    f.write_attr("version", kGruFormatVersion);
    f.write_attr("feature_set", std::string(feature_set_name(w.features)));
    f.write_attr("features", feature_list());
    f.write_attr("hidden", static_cast<long>(w.hidden));
    f.write_attr("ds_max_frac", w.ds_max_frac);
    auto put = [&](const std::string& name, const Eigen::MatrixXd& m, bool vector) {
      const RowMajor rm = m;
      std::vector<hsize_t> dims =
          vector ? std::vector<hsize_t>{static_cast<hsize_t>(m.size())}
                 : std::vector<hsize_t>{static_cast<hsize_t>(m.rows()), static_cast<hsize_t>(m.cols())};
      f.write(name, dims, std::vector<double>(rm.data(), rm.data() + rm.size()));
    };
    put("/gru/weight_ih", w.w_ih, false);
    put("/gru/weight_hh", w.w_hh, false);
    put("/gru/bias_ih", w.b_ih, true);
    put("/gru/bias_hh", w.b_hh, true);
    put("/head/weight", w.head_w.transpose(), false);
    put("/head/bias", Eigen::VectorXd::Constant(1, w.head_b), true);
    if (extra) extra(f);
  });
}

double gru_parity_error(const std::string& path) {
  const GruWeights w = load_gru_weights(path);
  const auto f = h5::File::open_read(path);
  std::vector<hsize_t> in_dims, out_dims;
  const auto inputs = f.read("/parity/inputs", in_dims);
  const auto outputs = f.read("/parity/residuals", out_dims);
  if (in_dims.size() != 3 || in_dims[2] != static_cast<hsize_t>(w.inputs) || out_dims.size() != 2 ||
      out_dims[0] != in_dims[0] || out_dims[1] != in_dims[1])
    throw InputError(path + ": /parity/inputs must be [T, B, " + std::to_string(w.inputs) +
                     "] and /parity/residuals [T, B]");
  const hsize_t T = in_dims[0], B = in_dims[1], F = in_dims[2];
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(w.hidden, static_cast<Eigen::Index>(B));
  double worst = 0;
  for (hsize_t t = 0; t < T; ++t)
    for (hsize_t b = 0; b < B; ++b) {
      const Eigen::Map<const Eigen::VectorXd> x(inputs.data() + (t * B + b) * F, static_cast<Eigen::Index>(F));
      h.col(b) = gru_step(w, x, h.col(b));
      worst = std::max(worst, std::fabs(gru_head(w, h.col(b)) - outputs[t * B + b]));
    }
  return worst;
}

std::string default_gru_weights_path() {
  if (const char* env = std::getenv("SEMLB_GRU_WEIGHTS")) return env;
  return SEMLB_DEFAULT_WEIGHTS;
}

std::string resolve_gru_weights(const std::string& path) {
  return resolve_weights_file(path, default_gru_weights_path());
}

namespace {

class GruPolicy final : public Policy {
 public:
  GruPolicy(GruWeights w, ReactiveParams p) : w_(std::move(w)), p_(p), tracker_(w_.ds_max_frac, w_.features) {}

  std::vector<int> decide(const Observation& obs) override {
    const auto inputs = tracker_.observe(obs, p_);
    if (hidden_.cols() != static_cast<Eigen::Index>(inputs.size()))
      hidden_ = Eigen::MatrixXd::Zero(w_.hidden, static_cast<Eigen::Index>(inputs.size()));  // first event
    std::vector<long> moves(inputs.size());
    for (size_t i = 0; i < inputs.size(); ++i) {
      const auto& in = inputs[i];
      hidden_.col(i) =
          gru_step(w_, Eigen::Map<const Eigen::VectorXd>(in.features.data(), kFeatureCount), hidden_.col(i));
      moves[i] = integer_step(in.direction,
                              residual_magnitude(in.reactive_magnitude, in.ds_max, gru_head(w_, hidden_.col(i))));
    }
    return apply_moves(obs.boundaries, moves, obs.slices, obs.min_width);
  }

  PolicyState save_state() const override {
    PolicyState s;
    tracker_.save_state(s);
    if (hidden_.size() > 0) s["hidden"].assign(hidden_.data(), hidden_.data() + hidden_.size());  // column-major H x B
    return s;
  }
  void load_state(const PolicyState& s) override {
    for (const auto& [k, v] : s)
      if (k != "hidden" && k.rfind("tracker.", 0) != 0) throw InputError("gru state: unknown entry '" + k + "'");
    tracker_.load_state(s);
    const auto h = s.find("hidden");
    if (h == s.end()) {
      hidden_.resize(0, 0);
      return;
    }
    const auto tracked = s.find("tracker.prev_imbalance");
    const size_t boundaries = tracked == s.end() ? 0 : tracked->second.size();
    if (h->second.size() != boundaries * w_.hidden)
      throw InputError("gru state: hidden has " + std::to_string(h->second.size()) +
                       " values, expected the hidden size " + std::to_string(w_.hidden) + " x " +
                       std::to_string(boundaries) + " boundaries");
    hidden_ = Eigen::Map<const Eigen::MatrixXd>(h->second.data(), w_.hidden,
                                                static_cast<Eigen::Index>(h->second.size() / w_.hidden));
  }

 private:
  GruWeights w_;
  ReactiveParams p_;
  FeatureTracker tracker_;
  Eigen::MatrixXd hidden_;  // H x B: one hidden state per boundary
};

const Registrar<PolicyInfo> gru_registrar(
    "gru", {[](PolicyParams& params) {
      ReactiveParams p;
      p.tau = params.real("tau", p.tau, 0.0, kMaxThreshold);
      p.alpha = params.real("alpha", p.alpha, 0.0, 2.0, true, true);
      const std::string path = params.text("weights", "");
      if (path.empty() && !std::filesystem::exists(default_gru_weights_path()))
        throw InputError("policy 'gru': no --weights given and the shipped default " + default_gru_weights_path() +
                         " does not exist (train one with `semlb train`)");
      return std::make_unique<GruPolicy>(load_gru_weights(resolve_gru_weights(path)), p);
    }});

}  // namespace

std::unique_ptr<Policy> make_gru_policy(GruWeights w, const ReactiveParams& p) {
  return std::make_unique<GruPolicy>(std::move(w), p);
}

}  // namespace semlb
