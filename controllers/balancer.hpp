// The rebalancing interval written once (paper Sec. IV; docs/design.md "The controller contract"): one interval's
// measurement -> validated Observation -> policy -> checked partition -> migration, I_global, trace event.
// The engine, the surrogate rollout and the trainer all go through a Balancer; its state is checkpointed.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "policy.hpp"
#include "trace.hpp"

namespace semlb {

// What one rebalancing interval measured. Sizes: times [P], slice_work and true_work [slices] or empty.
struct Measurement {
  std::vector<double> times;       // per-rank computation time of the interval (s, or work units if modelled)
  std::vector<double> slice_work;  // per-slice workload estimate (engine: W_s, paper eqs. 2-3); may be empty
  std::vector<double> true_work;   // noise-free work of the interval the decision governs; empty if unknown
  double growth_phase = 0.0;       // [0, 1)
  bool growth_event = false;
};

// One decision: the new boundaries [P-1], the slices moved, I_global of the measured times (paper eq. 7),
// the policy's wall time, and the trace line (observation + decision).
struct Decision {
  std::vector<int> boundaries;
  long moved = 0;
  double imbalance = 0.0;
  double seconds = 0.0;
  TraceEvent trace;
};

// The balancer's own state, saved in checkpoints (version kBalancerStateVersion).
inline constexpr long kBalancerStateVersion = 1;
struct BalancerState {
  int event = 0;                // index of the next event
  long migration = 0;           // slices moved so far
  std::vector<int> boundaries;  // current interior boundaries [P-1]
  PolicyState policy;           // the policy's history (Policy::save_state)
};

class Balancer {
 public:
  // `initial` must be a valid partition of `slices` into initial.size()+1 ranks of >= min_width slices
  // (InputError otherwise). `policy` may be null for callers that decide themselves (observe + commit).
  Balancer(std::string policy_name, std::unique_ptr<Policy> policy, int slices, int min_width,
           std::vector<int> initial);
  // Same with a policy the caller owns and keeps alive while the balancer is used.
  Balancer(std::string policy_name, Policy& policy, int slices, int min_width, std::vector<int> initial);

  // observe + policy->decide + commit. Throws InputError for an invalid measurement (naming the event and
  // field) and std::runtime_error naming the event and policy if the policy returns an invalid partition.
  Decision rebalance(Measurement m);
  // The validated Observation of event event() for this measurement (no state changes).
  Observation observe(Measurement m) const;
  // Checks `next`, counts its migration against the current boundaries and makes it current; advances the event.
  Decision commit(Observation obs, std::vector<int> next);

  int event() const { return event_; }
  int ranks() const { return static_cast<int>(boundaries_.size()) + 1; }
  int slices() const { return slices_; }
  int min_width() const { return min_width_; }
  const std::vector<int>& boundaries() const { return boundaries_; }
  long migration() const { return migration_; }
  const std::string& policy_name() const { return name_; }

  BalancerState save_state() const;
  // Restores a saved state; InputError if its boundaries do not fit this balancer (rank or slice count).
  void load_state(const BalancerState& s);

 private:
  std::string name_;
  std::unique_ptr<Policy> owned_;
  Policy* policy_ = nullptr;
  int slices_, min_width_;
  std::vector<int> boundaries_;
  int event_ = 0;
  long migration_ = 0;
};

}  // namespace semlb
