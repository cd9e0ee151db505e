// Training episodes: randomised scenarios from TRAINING seeds only, their noise-free workload trajectory,
// and the per-episode difficulty scale (the reactive rule's imbalance on the same episode).
#pragma once
#include <cstdint>
#include <vector>

#include "config.hpp"
#include "controllers/workload.hpp"
#include "surrogate/scenario.hpp"

namespace semlb::train {

struct Episode {
  surrogate::Scenario scenario;
  std::vector<std::vector<double>> work;  // W_t for t = 0..events (noise-free, per slice)
  std::vector<double> growth_phase;       // per event
  std::vector<char> growth_event;         // per event
  std::vector<int> initial_boundaries;    // workload-aware optimal partition of W_0
  double difficulty = 1.0;                // max(floor, reactive's mean (max-mean)/mean on this episode)
  double reactive_migration = 0;          // slices reactive moves on this episode
  std::string source = "synthetic";       // "synthetic", "front" or the workload file's index "workload:K"
};

// The workload files of c.workloads (comma-separated), read strictly (empty when none); InputError names the file.
std::vector<EngineWorkload> load_training_workloads(const TrainConfig& c);

// Episode `index` of optimisation step `step`: seed and rank count are pure functions of
// (config seed, step, index), so a resumed run sees the same episodes.
// `workloads`: load_training_workloads(c), needed when c.trace_fraction > 0 (std::logic_error otherwise).
Episode make_episode(const TrainConfig& c, long step, int index, const std::vector<EngineWorkload>& workloads = {});
// The batch of step `step`, generated on c.threads threads (same result for any thread count).
std::vector<Episode> make_batch(const TrainConfig& c, long step, const std::vector<EngineWorkload>& workloads = {});
// Reactive on the episode: time-averaged (max-mean)/mean over the intervals 1..events, and slices moved.
struct ReactiveCost {
  double max_over_mean = 0, migration = 0;
};
ReactiveCost reactive_cost(const Episode& e);

}  // namespace semlb::train
