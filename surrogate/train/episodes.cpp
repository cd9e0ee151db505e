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

namespace semlb::train {

Episode make_episode(const TrainConfig& c, long step, int index) {
  const auto& seeds = surrogate::kTrainSeeds;
  const uint64_t key = rng::bits(static_cast<uint64_t>(c.seed), 0x7261696eull, static_cast<uint64_t>(step), index);
  const uint64_t seed = seeds.first + key % (seeds.last - seeds.first + 1);
  const int ranks = static_cast<int>(c.ranks_min + rng::bits(key, 1, 0) % (c.ranks_max - c.ranks_min + 1));
  Episode e;
  e.scenario = surrogate::make_scenario(seed, ranks);
  surrogate::Workload w(e.scenario);
  for (long t = 0; t <= c.events; ++t) {
    e.work.push_back(w.work());
    e.growth_phase.push_back(w.growth_phase());
    e.growth_event.push_back(w.growth_event());
    w.advance();
  }
  e.initial_boundaries = optimal_partition(e.work[0], ranks, e.scenario.min_width);
  const auto reactive = reactive_cost(e);
  e.difficulty = c.imbalance_norm == "fixed" ? c.difficulty_floor : std::max(c.difficulty_floor, reactive.max_over_mean);
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

std::vector<Episode> make_batch(const TrainConfig& c, long step) {
  std::vector<Episode> batch(c.batch);
  std::vector<std::thread> workers;
  for (long w = 0; w < c.threads; ++w)
    workers.emplace_back([&, w] {
      for (long i = w; i < c.batch; i += c.threads) batch[i] = make_episode(c, step, static_cast<int>(i));
    });
  for (auto& t : workers) t.join();
  return batch;
}

}  // namespace semlb::train
