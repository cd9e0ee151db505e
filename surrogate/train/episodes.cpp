// Training episode generation (hash-keyed: no RNG state to checkpoint).
#include "episodes.hpp"

#include <algorithm>
#include <thread>

#include "controllers/balancer.hpp"
#include "controllers/chains.hpp"
#include "controllers/policy.hpp"
#include "surrogate/rng.hpp"
#include "controllers/metrics.hpp"
#include "controllers/partition.hpp"
#include "common/text_io.hpp"
#include "surrogate/workload_replay.hpp"

namespace semlb::train {

std::vector<EngineWorkload> load_training_workloads(const TrainConfig& c) {
  std::vector<EngineWorkload> out;
  if (c.workloads.empty()) return out;
  for (const auto& path : split(c.workloads, ',')) out.push_back(read_workload(path));
  return out;
}

namespace {

// A window of a recorded engine workload (surrogate/workload_replay.hpp's track: W_s per slice, coarsened), at a rank
// count that fits; the scenario carries only what the rollout reads (seed, ranks, slices, min width, jitter).
void trace_episode(Episode& e, const TrainConfig& c, uint64_t key, uint64_t seed,
                   const std::vector<EngineWorkload>& workloads) {
  const size_t k = rng::bits(key, 2, 0) % workloads.size();
  const EngineWorkload& w = workloads[k];
  surrogate::WorkloadReplay r;
  r.coarsen = 1 + static_cast<int>(rng::bits(key, 3, 0) % static_cast<uint64_t>(c.trace_coarsen_max));
  while (r.coarsen > 1 &&
         w.slices / r.coarsen < 2 * static_cast<int>(c.ranks_max) * ((w.min_width + r.coarsen - 1) / r.coarsen))
    --r.coarsen;
  const int slices = w.slices / r.coarsen, min_width = (w.min_width + r.coarsen - 1) / r.coarsen;
  const int fit = std::max(2, std::min(static_cast<int>(c.ranks_max), slices / min_width));
  const int lo = std::min(static_cast<int>(c.ranks_min), fit);
  r.ranks = lo + static_cast<int>(rng::bits(key, 4, 0) % static_cast<uint64_t>(fit - lo + 1));
  const int E = static_cast<int>(w.events.size()), want = static_cast<int>(c.events) + 1;
  r.events = std::min(E, want);
  r.first_event = E > want ? static_cast<int>(rng::bits(key, 5, 0) % static_cast<uint64_t>(E - want + 1)) : 0;
  const auto track = surrogate::replay_track(w, r, "workload " + std::to_string(k));
  e.scenario = surrogate::Scenario{};
  e.scenario.seed = seed;
  e.scenario.ranks = r.ranks;
  e.scenario.slices = track.slices;
  e.scenario.min_width = track.min_width;
  e.scenario.time_jitter = rng::uniform(0.005, c.trace_jitter_max, key, 6, 0);
  for (int t = 0; t < want; ++t) {  // a window shorter than the rollout holds its last event
    const int at = std::min(t, static_cast<int>(track.work.size()) - 1);
    e.work.push_back(track.work[at]);
    e.growth_phase.push_back(track.phase[at]);
    e.growth_event.push_back(track.growth[at]);
  }
  e.source = "workload:" + std::to_string(k);
}

}  // namespace

Episode make_episode(const TrainConfig& c, long step, int index, const std::vector<EngineWorkload>& workloads) {
  const auto& seeds = surrogate::kTrainSeeds;
  const uint64_t key = rng::bits(static_cast<uint64_t>(c.seed), 0x7261696eull, static_cast<uint64_t>(step), index);
  const uint64_t seed = seeds.first + key % (seeds.last - seeds.first + 1);
  const int ranks = static_cast<int>(c.ranks_min + rng::bits(key, 1, 0) % (c.ranks_max - c.ranks_min + 1));
  Episode e;
  const double kind = rng::uniform(key, 7, 0);  // which family: trace, front, plain synthetic
  if (kind < c.trace_fraction) {
    if (workloads.empty()) throw std::logic_error("make_episode: trace_fraction > 0 without workloads");
    trace_episode(e, c, key, seed, workloads);
  } else {
    surrogate::ScenarioSet front;
    if (kind <
        c.trace_fraction + (1 - c.trace_fraction) * c.front_fraction) {  // a proliferative front crossing the axis
      front["front_amplitude"] = format_real(rng::uniform(0.5, 4.0, key, 8, 0));
      front["front_speed"] = format_real(rng::uniform(0.002, 0.012, key, 8, 1));
      front["front_start"] = format_real(rng::uniform(0.0, 0.5, key, 8, 2));
      e.source = "front";
    }
    e.scenario = surrogate::make_scenario(seed, ranks, front);
    surrogate::Workload w(e.scenario);
    for (long t = 0; t <= c.events; ++t) {
      e.work.push_back(w.work());
      e.growth_phase.push_back(w.growth_phase());
      e.growth_event.push_back(w.growth_event());
      w.advance();
    }
  }
  e.initial_boundaries = optimal_partition(e.work[0], e.scenario.ranks, e.scenario.min_width);
  const auto reactive = reactive_cost(e);
  e.difficulty =
      c.imbalance_norm == "fixed" ? c.difficulty_floor : std::max(c.difficulty_floor, reactive.max_over_mean);
  e.reactive_migration = reactive.migration;
  return e;
}

ReactiveCost reactive_cost(const Episode& e) {
  Balancer reactive("reactive", make_policy("reactive"), e.scenario.slices, e.scenario.min_width, e.initial_boundaries);
  ReactiveCost cost;
  for (size_t t = 0; t + 1 < e.work.size(); ++t) {  // the surrogate rollout's loop, without the unused work proxy
    Measurement m;
    m.times = surrogate::measured_times(e.scenario, static_cast<int>(t), rank_sums(e.work[t], reactive.boundaries()));
    m.growth_phase = e.growth_phase[t];
    m.growth_event = e.growth_event[t];
    reactive.rebalance(std::move(m));
    cost.max_over_mean += max_over_mean(rank_sums(e.work[t + 1], reactive.boundaries()));
  }
  cost.migration = reactive.migration();
  if (e.work.size() > 1) cost.max_over_mean /= static_cast<double>(e.work.size() - 1);
  return cost;
}

std::vector<Episode> make_batch(const TrainConfig& c, long step, const std::vector<EngineWorkload>& workloads) {
  std::vector<Episode> batch(c.batch);
  std::vector<std::thread> workers;
  for (long w = 0; w < c.threads; ++w)
    workers.emplace_back([&, w] {
      for (long i = w; i < c.batch; i += c.threads) batch[i] = make_episode(c, step, static_cast<int>(i), workloads);
    });
  for (auto& t : workers) t.join();
  return batch;
}

}  // namespace semlb::train
