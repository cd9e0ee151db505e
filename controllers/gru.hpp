// GRU controller: weights (HDF5 format v1), one Eigen GRU step, and the residual boundary rule (eq. 6).
#pragma once
#include <Eigen/Dense>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "features.hpp"

namespace semlb {

inline constexpr long kGruFormatVersion = 1;

// PyTorch nn.GRU layout: gate blocks ordered (reset r, update z, new n).
struct GruWeights {
  int hidden = 24;
  int inputs = 12;
  FeatureSet features = FeatureSet::v1;  // the input transforms it was trained with (attribute feature_set)
  double ds_max_frac = 0.5;              // Δs_max = ds_max_frac * N_slow at each boundary
  Eigen::MatrixXd w_ih;                  // 3H x F
  Eigen::MatrixXd w_hh;                  // 3H x H
  Eigen::VectorXd b_ih, b_hh;            // 3H
  Eigen::VectorXd head_w;                // H
  double head_b = 0.0;

  // Uniform(-1/sqrt(H), 1/sqrt(H)) like PyTorch's default, with the linear head set to zero.
  static GruWeights random_zero_head(int hidden, int inputs, uint64_t seed);
  long parameter_count() const;
};

// h' = GRU(x, h); residual r = head_w . h' + head_b.
Eigen::VectorXd gru_step(const GruWeights& w, const Eigen::VectorXd& x, const Eigen::VectorXd& h);
double gru_head(const GruWeights& w, const Eigen::VectorXd& h);

// Residual boundary step magnitude (paper eq. 6): Δs_max tanh(atanh(clip(|Δs_r|/Δs_max)) + r), >= 0.
// With r == 0 the identity tanh(atanh(u)) = u is applied exactly, so a zero head reproduces reactive.
double residual_magnitude(double reactive_magnitude, double ds_max, double residual);

// A gru policy from weights in memory (the trainer validates with it); reactive parameters as given.
struct ReactiveParams;
class Policy;
std::unique_ptr<Policy> make_gru_policy(GruWeights w, const ReactiveParams& p);

// File I/O. Loading checks format, version, feature set and list, and every shape; errors name the file.
// `extra` may add metadata or datasets before the file is renamed into place.
namespace h5 {
class File;
}
GruWeights load_gru_weights(const std::string& path);
void save_gru_weights(const std::string& path, const GruWeights& w, const std::function<void(h5::File&)>& extra = {});

// Largest |residual - recorded| over the file's parity record (/parity/inputs [T,B,F], /parity/residuals
// [T,B]), replayed through gru_step/gru_head with one hidden state per boundary. InputError if absent.
double gru_parity_error(const std::string& path);

// The shipped default weights file (may not exist yet).
std::string default_gru_weights_path();
// The file a `weights` parameter names: empty -> default_gru_weights_path(); a bare file name that does not exist
// here -> that name in the shipped weights folder (controllers/weights/, e.g. "gru_migration_penalty_8.h5") if it
// is there; anything else as given (load_gru_weights reports a missing file).
std::string resolve_gru_weights(const std::string& path);

}  // namespace semlb
