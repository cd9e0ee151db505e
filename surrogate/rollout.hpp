// Hard-integer rollouts of one policy on one scenario, and the per-rollout metrics (paper Sec. V-E).
#pragma once
#include <string>
#include <vector>

#include "controllers/policy.hpp"
#include "controllers/trace.hpp"
#include "scenario.hpp"

namespace semlb::surrogate {

struct RolloutResult {
  int events = 0;
  double mean_imbalance = 0;      // time-averaged I_global over the K events (noise-free times)
  double mean_max_over_mean = 0;  // time-averaged (T_max - T_mean)/T_mean
  double first_quarter_imbalance = 0, last_quarter_imbalance = 0;
  long migration = 0;             // M = sum over events and boundaries of |Δs|
  double us_per_decision = 0;     // policy wall time per decide() call, microseconds
  std::vector<double> imbalance;  // I_global per event
  std::vector<TraceEvent> trace;  // filled when asked for
};

// Fills mean_imbalance, the quarter means and mean_max_over_mean (= max_over_mean_sum / events) from res.imbalance.
void summarise(RolloutResult& res, double max_over_mean_sum);

// Event t: the interval runs with the current boundaries under W_t (metrics from noise-free times), the
// policy sees noisy times and work (and W_{t+1} as oracle_work), and its boundaries govern interval t+1.
// The initial partition is the workload-aware optimal partition of W_0. Throws std::runtime_error naming
// the event, rank and quantity if a non-finite value appears. The offline `foresight` is handed to
// foresight_rollout (solved over the whole run; no trace).
RolloutResult rollout(const Scenario& s, Policy& policy, int events, bool keep_trace = false);

// The offline perfect-foresight path (controllers/foresight.hpp) on the same workload: interval 0 runs with
// the same initial partition, intervals 1..K-1 with the boundaries foresight_path chooses knowing W_1..W_{K-1}.
// Metrics as rollout()'s (noise-free times); migration counts the K-1 transitions (no decision after the
// last interval); us_per_decision is the solve's wall time per event; no trace.
RolloutResult foresight_rollout(const Scenario& s, double lambda, int events);

// `semlb replay --score`: `policy` run on recorded work. events[t].obs.slice_work is the true work of interval
// t; from events[0]'s boundaries, interval t's times are the sums of that work over the policy's own partition
// in force, I_global and (T_max - T_mean)/T_mean come from them, and the policy sees those times (with the
// line's slice_work, growth fields, and slice_work of line t+1 as oracle_work, its own at the last line) and
// decides the next partition. Migration sums every decision (K, as rollout()). A ForesightPolicy is solved
// offline on the same work instead. lines[t]: line number of event t in `file`, for errors, which read
// "FILE:LINE: field 'F': reason" (slice_work missing, slices or min_width changing, a policy's refusal).
RolloutResult replay_rollout(const std::vector<TraceEvent>& events, const std::vector<long>& lines,
                             const std::string& file, Policy& policy, const std::string& name);

}  // namespace semlb::surrogate
