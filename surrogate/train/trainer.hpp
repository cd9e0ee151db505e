// `semlb train`: Adam + cosine annealing + clipping over soft rollouts, validation on validation seeds
// with the hard controller, checkpoints that resume after a kill, and export to the HDF5 weights format.
#pragma once
#include <string>

#include "config.hpp"

namespace semlb::train {

struct TrainOptions {
  std::string out;         // weights file (.h5), written last (tmp + rename)
  std::string checkpoint;  // default: OUT.ckpt
  std::string log;         // validation log CSV; default: OUT with .log.csv
  std::string git_revision = "unknown";
  bool progress = true;
};

struct TrainSummary {
  long steps = 0;
  double seconds = 0;
  double val_imbalance = 0, val_migration = 0;            // final weights, validation seeds
  double reactive_imbalance = 0, reactive_migration = 0;  // reactive on the same rollouts
  double parity_error = 0;
};

TrainSummary run_training(const TrainConfig& c, const TrainOptions& o);

// Seconds per phase of `steps` optimisation steps (no prefetch: each phase timed on its own).
struct StepTiming {
  double episodes = 0, forward = 0, backward = 0, optimiser = 0;
};
StepTiming time_training_steps(const TrainConfig& c, long steps);

// The trainer's functions as one table, for the callers that load this library when they first train
// (experiments/trainer_module.hpp): a process that does not train then never loads libtorch, whose start-up (dynamic
// linking and static initialisers) took 0.6 s of every semlb process on the development machine.
struct Entry {
  TrainConfig (*load_train_config)(const std::string& path, const std::vector<std::string>& overrides);
  std::string (*to_yaml)(const TrainConfig& c);
  TrainSummary (*run_training)(const TrainConfig& c, const TrainOptions& o);
  StepTiming (*time_training_steps)(const TrainConfig& c, long steps);
};

}  // namespace semlb::train

// The table, under a C name for dlsym (the types and exceptions are C++: one build, one runtime).
extern "C" const semlb::train::Entry* semlb_train_entry();
