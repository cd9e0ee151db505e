// Offline fit of learned_repartition's parameters (NLopt, derivative-free) on recorded workloads and synthetic scenarios.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "controllers/learned_repartition.hpp"

namespace semlb::fit {

// The fit's settings (surrogate/fit/learned_repartition.yaml; docs/train.md "learned_repartition"). Workload files
// are replayed (surrogate/workload_replay.hpp, default time model) at every rank count of `ranks` with every replay
// seed; synthetic scenarios are the paper's family (surrogate/scenario.hpp) on `surrogate_episodes` training seeds
// (0..N-1), the rank counts taken in turn. Validation uses its own files and the validation seeds 8000-8999.
struct FitConfig {
  std::vector<std::string> workloads, validation;  // training and validation workload files
  std::string ranks = "2,4,8,16", replay_seeds = "100,101", validation_surrogate_seeds = "8000-8007";
  long surrogate_episodes = 16, surrogate_events = 100;
  double surrogate_weight = 0.25;  // the synthetic episodes' share of the objective
  long evaluations = 300;          // global search (NLopt GN_CRS2_LM)
  long polish = 100;               // local search from its best (NLopt LN_SBPLX)
  long seed = 1, threads = 2;
};
// YAML keys as the fields' names (workloads and validation: comma-separated files); --set KEY=VALUE overrides. Strict:
// an unknown key, a number out of range or a missing file is an InputError naming the file, line and field.
FitConfig load_fit_config(const std::string& path, const std::vector<std::string>& overrides);

// The objective of one episode set: the mean over its episodes of loop(theta) / loop(base), base = all-zero
// parameters (the quantile cut, every event). A workload episode's loop is replay_workload's loop_s (computation plus
// migration seconds); a synthetic one's, in units of the mean rank time, is sum_t (1 + (T_max - T_mean)/T_mean) +
// migration P / S (a moved slice costs one interval of its computation, as migrate_s_per_slice does in the replay).
// The two kinds are weighted (1 - surrogate_weight) : surrogate_weight when both are present.
class EpisodeSet {
 public:
  EpisodeSet(const FitConfig& c, bool validation);
  double objective(const RepartitionParams& p) const;
  size_t size() const { return workload_episodes_.size() + surrogate_episodes_.size(); }

 private:
  struct WorkloadEpisode;
  struct SurrogateEpisode;
  std::vector<double> losses(const RepartitionParams& p) const;  // per episode, unnormalised
  const FitConfig& c_;
  std::vector<std::shared_ptr<const WorkloadEpisode>> workload_episodes_;
  std::vector<std::shared_ptr<const SurrogateEpisode>> surrogate_episodes_;
  std::vector<double> base_;
};

struct FitCandidate {
  std::string name;  // base, global, polished
  RepartitionParams params;
  double train = 0, validation = 0;
};
struct FitResult {
  std::vector<FitCandidate> candidates;
  size_t chosen = 0;  // the lowest validation objective
  long evaluations = 0;
  double seconds = 0;
};
struct FitOptions {
  std::string out, log;  // weights file; CSV of every evaluation (default: OUT with .log.csv)
  std::string git_revision;
  bool progress = true;
};
// Fits, chooses among the candidates by validation, writes OUT (tmp + rename) and the log. InputError on bad input.
FitResult run_fit(const FitConfig& c, const FitOptions& o);

}  // namespace semlb::fit
