// Offline fit of learned_repartition's parameters (NLopt, derivative-free) on recorded workloads and synthetic
// scenarios.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "controllers/learned_repartition.hpp"

namespace semlb {
class Policy;
}

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
  double regret_weight = 2.0;      // an episode's excess over its reference counts 1 + regret_weight times
  long evaluations = 300;          // global search (NLopt GN_CRS2_LM)
  long polish = 100;               // local search from its best (NLopt LN_SBPLX)
  long seed = 1, threads = 2;
  bool grid = true;               // also offer validation a coarse grid over gain x noise_floor x fixed_cost
  std::vector<std::string> free;  // the parameters searched (comma-separated names; default all); the others stay 0
};
// YAML keys as the fields' names (workloads and validation: comma-separated files); --set KEY=VALUE overrides. Strict:
// an unknown key, a number out of range or a missing file is an InputError naming the file, line and field.
FitConfig load_fit_config(const std::string& path, const std::vector<std::string>& overrides);

// The objective of one episode set: the mean over its episodes of loop(theta) / loop(reference), the reference the
// lower of the base rule's (all-zero parameters: the quantile cut, every event) and static's (never a move). A workload
// episode's loop is replay_workload's loop_s (computation plus migration seconds); a synthetic one's, in units of the
// mean rank time, is sum_t (1 + (T_max - T_mean)/T_mean) + migration P / S (a moved slice costs one interval of its
// computation, as migrate_s_per_slice does in the replay). An episode's ratio r counts r + regret_weight max(r - 1, 0):
// losing to the reference weighs more than winning (the targets are "never above static's" and "within 1% of the
// best"). The two kinds are weighted (1 - surrogate_weight) : surrogate_weight when both are present.
class EpisodeSet {
 public:
  EpisodeSet(const FitConfig& c, bool validation);
  double objective(const RepartitionParams& p) const;
  size_t size() const { return workload_episodes_.size() + surrogate_episodes_.size(); }

 private:
  struct WorkloadEpisode;
  struct SurrogateEpisode;
  std::vector<double> losses(const std::function<std::unique_ptr<Policy>()>& make) const;  // per episode, unnormalised
  const FitConfig& c_;
  std::vector<std::shared_ptr<const WorkloadEpisode>> workload_episodes_;
  std::vector<std::shared_ptr<const SurrogateEpisode>> surrogate_episodes_;
  std::vector<double> base_;
};

struct FitCandidate {
  std::string name;  // base, global, polished, shortlist N (the next-best points of the search by training objective)
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
// Fits (the global search, then the local one from its best), shortlists the 12 next-best points it evaluated, adds
// the coarse grid (48 points: gain 0.05, 0.13, 0.3, 0.5 x noise_floor 0, 0.03, 0.06, 0.1 x fixed_cost 0, 0.011,
// 0.03) when `grid`, chooses among them all by validation, writes OUT (tmp + rename) and the log. InputError on bad
// input.
FitResult run_fit(const FitConfig& c, const FitOptions& o);

}  // namespace semlb::fit
