// learned_repartition: W_s corrected toward the measured rank times, cut where it splits evenly, moved when it pays.
#pragma once
#include <array>
#include <map>
#include <memory>
#include <string>

namespace semlb {

class Policy;

inline constexpr long kRepartitionFormatVersion = 1;

// The learned parameters (all zero: the base rule, `persistence` with cut=quantile, exactly). Per decision, with t_r
// the measured rank times, w_s the slice work W_s scaled to sum(t), c_s a per-slice correction (1 at the start):
//   gain g, noise_floor e: for each rank r with gap x = log(t_r / sum_{s in r} w_s c_s), c_s *= exp(g soft(x, e)) for
//     its slices (soft(x, e) = sign(x) max(|x| - e, 0): a gap within the measurement noise is left alone), then
//     sum w c is rescaled to sum w (the W_s-to-time gap per region, learned online at the rate g; c in [0.1, 10]);
//   trend k: forecast f_s = max(0, e_s + k (e_s - e'_s)), e = w c this event, e' the last event's;
//   deadband d: the equal-share cut of f (equal_share_targets) keeps a boundary whose target is within d S slices (a
//     fraction of the domain, so that it means the same at any slice count);
//   move_cost m, fixed_cost m0: boundary k moves to its target only when that lowers the larger forecast work of its
//     two ranks (its neighbours at their targets) by more than m sum(t)/S per slice it moves, and no boundary moves
//     unless the gains of those that do exceed m0 sum(t)/P (costs in slice-intervals and rank-intervals of the
//     interval just measured; both 0: every target is taken).
struct RepartitionParams {
  double gain = 0, noise_floor = 0, trend = 0, deadband = 0, move_cost = 0, fixed_cost = 0;
};

// One parameter's name, field and range [min, max] (weights files and policy parameters are checked against it).
struct RepartitionParam {
  const char* name;
  double RepartitionParams::*field;
  double min, max;
};
const std::array<RepartitionParam, 6>& repartition_params();

// A learned_repartition policy with these parameters (the fitter builds it directly).
std::unique_ptr<Policy> make_learned_repartition(const RepartitionParams& p);

// Weights file (HDF5): attributes format "semlb-learned-repartition", version kRepartitionFormatVersion and one real
// per parameter; `meta` adds text attributes (training provenance). Loading refuses a wrong format or version, a
// missing parameter, and a value outside its range or not finite, each an InputError naming the file and attribute.
RepartitionParams load_repartition_weights(const std::string& path);
void save_repartition_weights(const std::string& path, const RepartitionParams& p,
                              const std::map<std::string, std::string>& meta = {});
// The shipped weights (controllers/weights/learned_repartition/default.h5; env SEMLB_REPARTITION_WEIGHTS), and the
// file a `weights` parameter names: empty -> the default, a bare name found in that folder -> it, else as given.
std::string default_repartition_weights_path();
std::string resolve_repartition_weights(const std::string& path);

}  // namespace semlb
