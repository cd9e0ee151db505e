// Trainer hyper-parameters (paper Sec. IV-E defaults), loadable from YAML with --set overrides.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace semlb::train {

struct TrainConfig {
  long steps = 6000;                // optimisation steps
  long batch = 32;                  // episodes per step
  long events = 50;                 // rebalancing events per training rollout
  long bptt = 0;                    // truncate backpropagation every `bptt` events (0: through all events)
  double lr = 3e-3;                 // Adam initial learning rate
  double lr_final_frac = 0.05;      // cosine annealing down to lr * lr_final_frac
  double clip = 1.0;                // gradient-norm clipping
  double temp_start = 1.5;          // soft boundary-assignment temperature (slices), annealed linearly...
  double temp_end = 0.4;            // ...to this value at the last step
  double spread_weight = 0.3;       // weight of the normalised spread std/mean in the loss
  double migration_penalty = 5e-4;  // L1 penalty per moved slice
  double difficulty_floor = 0.005;  // lower bound of the per-episode difficulty scale
  // Loss forms (docs/train.md): "reactive" divides the imbalance terms by the episode's difficulty (paper);
  // "fixed" divides them by difficulty_floor for every episode (absolute units).
  std::string imbalance_norm = "reactive";
  // "slices": migration_penalty per moved slice (paper); "reactive": migration_penalty x (slices moved /
  // slices reactive moves on the same episode), i.e. a penalty on the migration ratio.
  std::string migration_norm = "slices";
  long hidden = 24;                    // GRU hidden size
  double ds_max_frac = 0.5;            // Δs_max = ds_max_frac * N_slow
  long ranks_min = 2, ranks_max = 16;  // episode rank counts (uniform)
  long seed = 1;                       // model init + episode sampling
  long threads = 1;           // episode-generation threads (beside the training thread); any count gives the same run
  long validate_every = 250;  // steps between validation rollouts (0: only at the end)
  std::string validation_seeds = "8000-8007";  // validation range only (8000-8999)
  std::string validation_ranks = "2,4,8,16";
  long validation_events = 100;
  long checkpoint_every = 100;  // steps between checkpoints
  // The GRU's input transforms (controllers/features.hpp): boundary-v1 (clamped; the synthetic-only gru_v1 weights)
  // or boundary-v2 (squashed: keeps its meaning at imbalances of 100% and more).
  std::string features = "boundary-v1";
  // Trace-driven episodes (docs/train.md "Engine workloads"): a fraction `trace_fraction` of the episodes replays a
  // window of `events + 1` events of one of the comma-separated workload files (training split only; paths relative to
  // the working directory), at a random rank count in [ranks_min, ranks_max] that fits, with 1..trace_coarsen_max
  // adjacent slices merged and a time jitter (relative std) drawn uniformly in [0.005, trace_jitter_max] (0.03: a
  // synthetic scenario's range; the time model's measured jitter is 0.03). Of the synthetic episodes a fraction
  // `front_fraction` carries a moving proliferative front (scenario front_amplitude / front_speed / front_start).
  std::string workloads;
  double trace_fraction = 0.0;
  double front_fraction = 0.0;
  long trace_coarsen_max = 4;
  double trace_jitter_max = 0.03;
};

// Loads FILE (may be empty: defaults) then KEY=VALUE overrides, read by semlb::Settings (common/settings.hpp): a
// value outside its range, an unknown key or a bad combination is an InputError naming the file, line and field
// ("bad.yaml:2: field 'batch': '0' is outside [1, ...]") or the flag ("--set batch: ...").
TrainConfig load_train_config(const std::string& path, const std::vector<std::string>& overrides);
// Every key as "key: value" lines (stored in the weights file and checked on resume).
std::string to_yaml(const TrainConfig& c);

}  // namespace semlb::train
