// Differentiable rollout: features and reactive pieces come from controllers/ (FeatureTracker) on the
// hard state; the GRU residual, eq. 6, the sweep and the soft rank times are torch operations.
#include "soft_rollout.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "controllers/balancer.hpp"
#include "controllers/features.hpp"
#include "controllers/partition.hpp"
#include "controllers/reactive.hpp"

namespace semlb::train {
namespace {

constexpr long kGuard = 12;  // window half-width (slices): sigmoid(12 / 1.5) = 0.9997

// Per-event padded work and exclusive prefix sums: Wpad[e, s + G] = W_t(e, s); Ppad[e, k] = sum Wpad[e, <k].
struct PaddedWork {
  torch::Tensor w, p, total;  // [E, L], [E, L + 1], [E, 1]
};

PaddedWork pad_work(const std::vector<const std::vector<double>*>& per_episode, long max_slices) {
  const long E = static_cast<long>(per_episode.size()), L = max_slices + 2 * kGuard + 1;
  std::vector<float> w(E * L, 0.f), p(E * (L + 1), 0.f), total(E, 0.f);
  for (long e = 0; e < E; ++e) {
    const auto& src = *per_episode[e];
    double run = 0;
    for (long k = 0; k < L; ++k) {
      const long s = k - kGuard;
      const double v = s >= 0 && s < static_cast<long>(src.size()) ? src[s] : 0.0;
      w[e * L + k] = static_cast<float>(v);
      p[e * (L + 1) + k] = static_cast<float>(run);
      run += v;
    }
    p[e * (L + 1) + L] = static_cast<float>(run);
    total[e] = static_cast<float>(run);
  }
  return {torch::from_blob(w.data(), {E, L}).clone(), torch::from_blob(p.data(), {E, L + 1}).clone(),
          torch::from_blob(total.data(), {E, 1}).clone()};
}

// Cumulative soft work left of each boundary [E, B] (boundaries hold integer values in the forward pass).
torch::Tensor soft_cumulative(const PaddedWork& pw, const torch::Tensor& b, double temperature) {
  const long E = b.size(0), B = b.size(1), window = 2 * kGuard + 1;
  const auto floor = b.detach().floor().to(torch::kLong);
  const auto offsets = torch::arange(window, torch::kLong);
  const auto idx = (floor.unsqueeze(2) + offsets).view({E, B * window});
  const auto wwin = pw.w.gather(1, idx).view({E, B, window});
  const auto centres = (floor - kGuard).unsqueeze(2).to(torch::kFloat) + offsets.to(torch::kFloat) + 0.5f;
  const auto left = torch::sigmoid((b.unsqueeze(2) - centres) / temperature);
  return pw.p.gather(1, floor) + (wwin * left).sum(2);
}

torch::Tensor rank_times(const PaddedWork& pw, const torch::Tensor& b, const torch::Tensor& bmask, double temperature) {
  const auto c = torch::where(bmask, soft_cumulative(pw, b, temperature), pw.total.expand_as(b));
  const auto full = torch::cat({torch::zeros({b.size(0), 1}), c, pw.total}, 1);
  return full.slice(1, 1) - full.slice(1, 0, -1);
}

}  // namespace

torch::Tensor soft_rank_times(const std::vector<double>& work, const torch::Tensor& boundaries, double temperature) {
  const auto pw = pad_work({&work}, static_cast<long>(work.size()));
  const auto b = boundaries.view({1, -1});
  return rank_times(pw, b, torch::ones_like(b, torch::kBool), temperature).squeeze(0);
}

torch::Tensor soft_rollout_loss(Controller& model, const std::vector<Episode>& eps, const TrainConfig& c,
                                double temperature, SoftStats* stats) {
  const long E = static_cast<long>(eps.size());
  long B = 1, S = 1;
  for (const auto& e : eps) B = std::max<long>(B, e.scenario.ranks - 1), S = std::max<long>(S, e.scenario.slices);

  // Static per-episode tensors; padded boundary columns sit at the episode's last slice edge.
  std::vector<float> b0(E * B), right_edge(E), ranks(E), difficulty(E), migration_scale(E);
  std::vector<uint8_t> bmask(E * B, 0), rmask(E * (B + 1), 0);
  std::vector<long> flat;  // valid (episode, boundary) cells in row-major order
  for (long e = 0; e < E; ++e) {
    const auto& s = eps[e].scenario;
    right_edge[e] = static_cast<float>(s.slices);
    ranks[e] = static_cast<float>(s.ranks), difficulty[e] = static_cast<float>(eps[e].difficulty);
    migration_scale[e] =
        c.migration_norm == "reactive" ? 1.0f / std::max(1.0f, static_cast<float>(eps[e].reactive_migration)) : 1.0f;
    for (long i = 0; i < B; ++i) {
      const bool valid = i < s.ranks - 1;
      b0[e * B + i] = valid ? static_cast<float>(eps[e].initial_boundaries[i]) : right_edge[e];
      bmask[e * B + i] = valid;
      if (valid) flat.push_back(e * B + i);
    }
    for (long r = 0; r <= B; ++r) rmask[e * (B + 1) + r] = r < s.ranks;
  }
  const long N = static_cast<long>(flat.size());
  auto tensor = [](std::vector<float>& v, std::vector<long> shape) {
    return torch::from_blob(v.data(), shape).clone();
  };
  const auto bmask_t = torch::from_blob(bmask.data(), {E, B}, torch::kUInt8).to(torch::kBool);
  const auto rmask_t = torch::from_blob(rmask.data(), {E, B + 1}, torch::kUInt8).to(torch::kBool);
  const auto rmask_f = rmask_t.to(torch::kFloat);
  const auto ranks_t = tensor(ranks, {E});
  const auto difficulty_t = tensor(difficulty, {E}), migration_scale_t = tensor(migration_scale, {E});
  const auto flat_t = torch::from_blob(flat.data(), {N}, torch::kLong).clone();

  torch::Tensor b = tensor(b0, {E, B});
  std::vector<Balancer> hard;  // the deployed integer state: no policy, the GRU step below decides
  for (const auto& ep : eps)
    hard.emplace_back("gru", nullptr, ep.scenario.slices, ep.scenario.min_width, ep.initial_boundaries);
  std::vector<FeatureTracker> trackers(E, FeatureTracker(c.ds_max_frac, parse_feature_set(c.features, "")));
  torch::Tensor h = torch::zeros({N, model->hidden});
  torch::Tensor imbalance_terms = torch::zeros({E}), moved = torch::zeros({E});
  double raw_imbalance = 0;

  for (long t = 0; t < c.events; ++t) {
    if (c.bptt > 0 && t > 0 && t % c.bptt == 0) {  // truncated BPTT: same forward values, shorter gradients
      h = h.detach();
      b = b.detach();
    }
    // Observation of interval t on the hard state, through the controllers' own feature code.
    std::vector<float> x(N * kFeatureCount), dir(N), mag(N), dsmax(N);
    std::vector<Observation> observed(E);
    long n = 0;
    for (long e = 0; e < E; ++e) {
      const auto& ep = eps[e];
      Measurement m;
      m.times =
          surrogate::measured_times(ep.scenario, static_cast<int>(t), rank_sums(ep.work[t], hard[e].boundaries()));
      m.growth_phase = ep.growth_phase[t];
      m.growth_event = ep.growth_event[t];
      const Observation& obs = observed[e] = hard[e].observe(std::move(m));
      for (const auto& in : trackers[e].observe(obs, ReactiveParams{})) {
        std::copy(in.features.begin(), in.features.end(), x.begin() + n * kFeatureCount);
        dir[n] = static_cast<float>(in.direction), mag[n] = static_cast<float>(in.reactive_magnitude);
        dsmax[n] = static_cast<float>(in.ds_max);
        ++n;
      }
    }
    auto [h_next, r] = model->step(tensor(x, {N, kFeatureCount}), h);
    h = h_next;
    const auto dsmax_t = tensor(dsmax, {N});
    const auto u = torch::clamp(tensor(mag, {N}) / dsmax_t.clamp_min(1e-12), 0.0, 1.0 - 1e-6);
    const auto m = torch::relu(dsmax_t * torch::tanh(torch::atanh(u) + r));     // eq. 6
    const auto step = tensor(dir, {N}) * (m + (torch::round(m) - m).detach());  // straight-through rounding

    // The sweep is integer arithmetic: apply it exactly on the hard state (apply_moves, as deployed). A move
    // that was not truncated passes its gradient; a truncated boundary sits at a bound and gets none.
    const auto steps = step.detach().contiguous();
    const auto sa = steps.accessor<float, 1>();
    std::vector<float> next(E * B), free(E * B, 0.f);
    n = 0;
    for (long e = 0; e < E; ++e) {
      const auto& before = hard[e].boundaries();
      std::vector<long> moves(before.size());
      for (auto& mv : moves) mv = std::lround(sa[n++]);
      const auto moved_b = apply_moves(before, moves, eps[e].scenario.slices, eps[e].scenario.min_width);
      for (long i = 0; i < B; ++i) next[e * B + i] = i < static_cast<long>(moved_b.size()) ? moved_b[i] : right_edge[e];
      for (size_t i = 0; i < moved_b.size(); ++i) free[e * B + i] = moved_b[i] == before[i] + moves[i];
      hard[e].commit(std::move(observed[e]), moved_b);
    }
    const auto delta = torch::zeros({E * B}).index_add(0, flat_t, step).view({E, B});
    const auto b_next = torch::where(tensor(free, {E, B}).to(torch::kBool), b + delta, tensor(next, {E, B}));
    moved = moved + (b_next - b).abs().sum(1);
    b = b_next;

    // Interval t+1 under the new boundaries: soft times carry the gradient.
    std::vector<const std::vector<double>*> work_next;
    for (const auto& ep : eps) work_next.push_back(&ep.work[t + 1]);
    const auto T = rank_times(pad_work(work_next, S), b, bmask_t, temperature);
    const auto mean = (T * rmask_f).sum(1) / ranks_t;
    const auto max = T.masked_fill(~rmask_t, -1e30).amax(1);
    const auto spread = torch::sqrt((((T - mean.unsqueeze(1)) * rmask_f).pow(2)).sum(1) / ranks_t + 1e-12) / mean;
    const auto rel = (max - mean) / mean;
    raw_imbalance += rel.mean().item<double>();
    imbalance_terms = imbalance_terms + (rel + c.spread_weight * spread) / difficulty_t;
  }
  const auto loss =
      (imbalance_terms / static_cast<double>(c.events) + c.migration_penalty * migration_scale_t * moved).mean();
  if (stats) {
    stats->imbalance = raw_imbalance / c.events;
    stats->migration = moved.mean().item<double>();
  }
  return loss;
}

}  // namespace semlb::train
