// Hard-integer surrogate rollout.
#include "rollout.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "controllers/balancer.hpp"
#include "controllers/chains.hpp"
#include "controllers/foresight.hpp"
#include "common/errors.hpp"
#include "controllers/metrics.hpp"
#include "controllers/partition.hpp"

namespace semlb::surrogate {
namespace {

void check_finite(const std::vector<double>& v, int event, const char* quantity) {
  for (size_t r = 0; r < v.size(); ++r)
    if (!std::isfinite(v[r]))
      throw std::runtime_error("surrogate: event " + std::to_string(event) + ", rank " + std::to_string(r) + ": " +
                               quantity + " is not finite");
}

double mean_of(const std::vector<double>& v, size_t begin, size_t end) {
  double s = 0;
  for (size_t i = begin; i < end; ++i) s += v[i];
  return end > begin ? s / (end - begin) : 0.0;
}

}  // namespace

void summarise(RolloutResult& res, double max_over_mean_sum) {
  const int events = res.events;
  res.mean_imbalance = mean_of(res.imbalance, 0, events);
  res.mean_max_over_mean = max_over_mean_sum / events;
  const size_t q = std::max<size_t>(1, events / 4);
  res.first_quarter_imbalance = mean_of(res.imbalance, 0, q);
  res.last_quarter_imbalance = mean_of(res.imbalance, events - q, events);
}

RolloutResult rollout(const Scenario& s, Policy& policy, int events, bool keep_trace) {
  if (events < 1) throw InputError("events must be >= 1, got " + std::to_string(events));
  if (const auto* offline = dynamic_cast<const ForesightPolicy*>(&policy))  // solved over the whole run, no trace
    return foresight_rollout(s, offline->lambda(), events);
  Workload workload(s);
  Balancer balancer("", policy, s.slices, s.min_width, optimal_partition(workload.work(), s.ranks, s.min_width));
  RolloutResult res;
  res.events = events;
  double seconds = 0, max_over_mean_sum = 0;
  for (int t = 0; t < events; ++t) {
    const auto true_times = rank_sums(workload.work(), balancer.boundaries());
    check_finite(true_times, t, "computation time");
    res.imbalance.push_back(global_imbalance(true_times));
    max_over_mean_sum += max_over_mean(true_times);
    Measurement m;
    m.times = measured_times(s, t, true_times);
    m.slice_work = observed_work(s, t, workload.work());
    m.growth_phase = workload.growth_phase();
    m.growth_event = workload.growth_event();
    workload.advance();
    m.true_work = workload.work();
    auto d = balancer.rebalance(std::move(m));
    seconds += d.seconds;
    if (keep_trace) res.trace.push_back(std::move(d.trace));
  }
  res.migration = balancer.migration();
  summarise(res, max_over_mean_sum);
  res.us_per_decision = 1e6 * seconds / events;
  return res;
}

RolloutResult foresight_rollout(const Scenario& s, double lambda, int events) {
  if (events < 1) throw InputError("events must be >= 1, got " + std::to_string(events));
  Workload workload(s);
  std::vector<std::vector<double>> work;
  for (int t = 0; t < events; ++t) {
    if (t > 0) workload.advance();
    work.push_back(workload.work());
  }
  const auto start = std::chrono::steady_clock::now();
  const auto path = foresight_path(work, optimal_partition(work[0], s.ranks, s.min_width), s.min_width, lambda);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RolloutResult res;
  res.events = events;
  double max_over_mean_sum = 0;
  for (int t = 0; t < events; ++t) {
    const auto times = rank_sums(work[t], path.boundaries[t]);
    check_finite(times, t, "computation time");
    res.imbalance.push_back(global_imbalance(times));
    max_over_mean_sum += max_over_mean(times);
  }
  res.migration = path.migration;
  summarise(res, max_over_mean_sum);
  res.us_per_decision = 1e6 * seconds / events;
  return res;
}

RolloutResult replay_rollout(const std::vector<TraceEvent>& events, const std::vector<long>& lines,
                             const std::string& file, Policy& policy, const std::string& name) {
  if (events.empty()) throw InputError(file + ": the trace has no events");
  const Observation& first = events[0].obs;
  std::vector<std::vector<double>> work;
  for (size_t t = 0; t < events.size(); ++t) {
    const Observation& o = events[t].obs;
    const long line = lines.at(t);
    if (o.slice_work.empty())
      throw InputError(where(file, line, "slice_work") + "missing (--score takes it as the true work)");
    if (o.slices != first.slices) throw InputError(where(file, line, "slices") + "differs from the first event's");
    if (o.min_width != first.min_width)
      throw InputError(where(file, line, "min_width") + "differs from the first event's");
    if (o.times.size() != first.times.size())
      throw InputError(where(file, line, "times") + "rank count differs from the first event's");
    work.push_back(o.slice_work);
  }
  const int K = static_cast<int>(events.size());
  RolloutResult res;
  res.events = K;
  double max_over_mean_sum = 0, seconds = 0;
  auto account = [&](const std::vector<double>& times) {
    res.imbalance.push_back(global_imbalance(times));
    max_over_mean_sum += max_over_mean(times);
  };
  if (const auto* offline = dynamic_cast<const ForesightPolicy*>(&policy)) {
    const auto path = foresight_path(work, first.boundaries, first.min_width, offline->lambda());
    for (int t = 0; t < K; ++t) account(rank_sums(work[t], path.boundaries[t]));
    res.migration = path.migration;
  } else {
    Balancer balancer(name, policy, first.slices, first.min_width, first.boundaries);
    for (int t = 0; t < K; ++t) {
      const Observation& o = events[t].obs;
      Measurement m;
      m.times = rank_sums(work[t], balancer.boundaries());
      account(m.times);
      m.slice_work = o.slice_work;
      m.true_work = t + 1 < K ? work[t + 1] : work[t];
      m.growth_phase = o.growth_phase;
      m.growth_event = o.growth_event;
      try {
        seconds += balancer.rebalance(std::move(m)).seconds;
      } catch (const ObservationError& e) {
        throw InputError(where(file, lines[t], e.field) + e.what());
      } catch (const std::exception& e) {  // a policy's refusal or an invalid partition it returned
        throw InputError(where(file, lines[t], "") + e.what());
      }
    }
    res.migration = balancer.migration();
  }
  summarise(res, max_over_mean_sum);
  res.us_per_decision = 1e6 * seconds / K;
  return res;
}

}  // namespace semlb::surrogate
