// Balancer: the one implementation of a rebalancing event (measure -> observe -> decide -> check -> count).
#include "balancer.hpp"

#include <chrono>
#include <stdexcept>

#include "common/errors.hpp"
#include "metrics.hpp"
#include "partition.hpp"

namespace semlb {

Balancer::Balancer(std::string policy_name, std::unique_ptr<Policy> policy, int slices, int min_width,
                   std::vector<int> initial)
    : name_(std::move(policy_name)),
      owned_(std::move(policy)),
      policy_(owned_.get()),
      slices_(slices),
      min_width_(min_width),
      boundaries_(std::move(initial)) {
  check_partition(boundaries_, slices_, min_width_);
}

Balancer::Balancer(std::string policy_name, Policy& policy, int slices, int min_width, std::vector<int> initial)
    : Balancer(std::move(policy_name), nullptr, slices, min_width, std::move(initial)) {
  policy_ = &policy;
}

Observation Balancer::observe(Measurement m) const {
  Observation obs;
  obs.event = event_;
  obs.slices = slices_;
  obs.min_width = min_width_;
  obs.boundaries = boundaries_;
  obs.times = std::move(m.times);
  obs.slice_work = std::move(m.slice_work);
  obs.oracle_work = std::move(m.true_work);
  obs.growth_phase = m.growth_phase;
  obs.growth_event = m.growth_event;
  validate(obs);
  return obs;
}

Decision Balancer::commit(Observation obs, std::vector<int> next) {
  try {
    check_partition(next, slices_, min_width_);
  } catch (const InputError& e) {
    throw std::runtime_error("event " + std::to_string(event_) + ": " +
                             (name_.empty() ? std::string("the policy") : "policy '" + name_ + "'") +
                             " returned an invalid partition: " + e.what());
  }
  Decision d;
  d.moved = semlb::migration(boundaries_, next);
  d.imbalance = global_imbalance(obs.times);
  d.boundaries = next;
  d.trace = TraceEvent{std::move(obs), next};
  migration_ += d.moved;
  boundaries_ = std::move(next);
  ++event_;
  return d;
}

Decision Balancer::rebalance(Measurement m) {
  if (!policy_) throw std::logic_error("Balancer::rebalance: no policy (use observe + commit)");
  Observation obs = observe(std::move(m));
  const auto start = std::chrono::steady_clock::now();
  auto next = policy_->decide(obs);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Decision d = commit(std::move(obs), std::move(next));
  d.seconds = seconds;
  return d;
}

BalancerState Balancer::save_state() const {
  return {event_, migration_, boundaries_, policy_ ? policy_->save_state() : PolicyState{}};
}

void Balancer::load_state(const BalancerState& s) {
  if (static_cast<int>(s.boundaries.size()) != ranks() - 1)
    throw InputError("balancer state: " + std::to_string(s.boundaries.size() + 1) + " ranks, this run has " +
                     std::to_string(ranks()));
  check_partition(s.boundaries, slices_, min_width_);
  if (s.event < 0 || s.migration < 0) throw InputError("balancer state: negative event index or migration");
  if (policy_) policy_->load_state(s.policy);
  boundaries_ = s.boundaries;
  event_ = s.event;
  migration_ = s.migration;
}

}  // namespace semlb
