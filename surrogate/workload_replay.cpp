// Replay of engine workloads at any rank count through the time model (workload_replay.hpp).
#include "workload_replay.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "controllers/balancer.hpp"
#include "controllers/chains.hpp"
#include "controllers/foresight.hpp"
#include "controllers/metrics.hpp"
#include "controllers/partition.hpp"
#include "rng.hpp"
#include "scenario.hpp"

namespace semlb::surrogate {
namespace {

enum Stream : uint64_t { kSpeed = 101, kJitter = 102 };

std::vector<double> coarse(const std::vector<double>& v, int k, int n) {  // n coarse entries, the last takes the rest
  std::vector<double> out(n, 0.0);
  for (size_t i = 0; i < v.size(); ++i) out[std::min<size_t>(i / k, n - 1)] += v[i];
  return out;
}

std::vector<double> coarse_edges(const std::vector<double>& v, int k, int n) {  // coarse edge j = fine edge j k
  std::vector<double> out(n - 1);
  for (int j = 1; j < n; ++j) out[j - 1] = v[static_cast<size_t>(j) * k - 1];
  return out;
}

std::vector<int64_t> coarse_bits(const std::vector<int64_t>& v, int k, int n) {  // OR of each coarse slice's bits
  std::vector<int64_t> out(n, 0);
  for (size_t i = 0; i < v.size(); ++i) out[std::min<size_t>(i / k, n - 1)] |= v[i];
  return out;
}

}  // namespace

const std::vector<std::string>& time_model_keys() {
  static const std::vector<std::string> keys = {
      "ghost_weight", "speed_spread", "jitter",      "migrate_s_per_slice", "seconds_per_work", "rank_overhead_s",
      "truth",        "list_by",      "list_weight", "list_element_weight", "element_s"};
  return keys;
}

void set_time_model(TimeModel& m, const std::string& key, const std::string& value, const std::string& where) {
  const std::string at = where + key + ": ";
  if (key == "ghost_weight")
    m.ghost_weight = parse_real(value, at, 0, 100);
  else if (key == "speed_spread")
    m.speed_spread = parse_real(value, at, 0, 0.3);
  else if (key == "jitter")
    m.jitter = parse_real(value, at, 0, 0.3);
  else if (key == "migrate_s_per_slice")
    m.migrate_s_per_slice = parse_real(value, at, 0, 1e6);
  else if (key == "seconds_per_work")
    m.seconds_per_work = parse_real(value, at, 0, 1e6);
  else if (key == "rank_overhead_s")
    m.rank_overhead_s = parse_real(value, at, 0, 1e6);
  else if (key == "element_s")
    m.element_s = parse_real(value, at, 0, 1);
  else if (key == "list_weight")
    m.list_weight = parse_real(value, at, 0, 100);
  else if (key == "list_element_weight")
    m.list_element_weight = parse_real(value, at, 0, 100);
  else if (key == "list_by") {
    if (value == "stages")
      m.list_by = TimeModel::ListBy::kStages;
    else if (value == "work")
      m.list_by = TimeModel::ListBy::kWork;
    else if (value == "triggers")
      m.list_by = TimeModel::ListBy::kTriggers;
    else
      throw InputError(at + "'" + value + "' is not one of stages, work, triggers");
  } else if (key == "truth") {
    if (value == "auto")
      m.truth = TimeModel::Truth::kAuto;
    else if (value == "work")
      m.truth = TimeModel::Truth::kWork;
    else if (value == "measured")
      m.truth = TimeModel::Truth::kMeasured;
    else
      throw InputError(at + "'" + value + "' is not one of auto, work, measured");
  } else {
    std::string known;
    for (const auto& k : time_model_keys()) known += (known.empty() ? "" : ", ") + k;
    throw InputError(at + "unknown time model key (known: " + known + ")");
  }
  m.given.insert(key);
}

ReplayTrack replay_track(const EngineWorkload& w, const WorkloadReplay& r, const std::string& file) {
  const int E = static_cast<int>(w.events.size());
  if (r.coarsen < 1 || r.coarsen > w.slices)
    throw InputError(file + ": coarsen " + std::to_string(r.coarsen) + " outside [1, slices]");
  if (r.first_event < 0 || r.first_event >= E)
    throw InputError(file + ": field 'events': first event " + std::to_string(r.first_event) + " outside the " +
                     std::to_string(E) + " recorded");
  const int last = r.events > 0 ? std::min(E, r.first_event + r.events) : E;
  ReplayTrack t;
  t.slices = w.slices / r.coarsen;
  t.min_width = (w.min_width + r.coarsen - 1) / r.coarsen;
  if (static_cast<long>(r.ranks) * t.min_width > t.slices || r.ranks < 1)
    throw InputError(file + ": --ranks " + std::to_string(r.ranks) + ": " + std::to_string(r.ranks) +
                     " ranks of at least " + std::to_string(t.min_width) + " slices do not fit in " +
                     std::to_string(t.slices) + " slices");
  const bool has = has_measured_cost(w);
  if (r.model.truth == TimeModel::Truth::kMeasured && !has)
    throw InputError(file +
                     ": field 'slice_seconds': --time-model truth=measured, but the file has no measured seconds "
                     "(a version 1 workload: record it with decomposition.timing: device)");
  t.measured = has && r.model.truth != TimeModel::Truth::kWork;
  // the list keys act on a version 3 file's list seconds under a measured truth: elsewhere they would do nothing
  for (const char* key : {"list_by", "list_weight", "list_element_weight", "element_s"})
    if (r.model.given.count(key)) {
      if (w.events.empty() || w.events.front().part_seconds.empty())
        throw InputError(file + ": time model " + key + ": the file has no list seconds (part_seconds: a version 3 " +
                         "workload)");
      if (!t.measured)
        throw InputError(file + ": time model " + key + ": truth=work replays W_s, which has no list seconds");
    }
  if (r.model.list_by == TimeModel::ListBy::kTriggers && w.events.front().list_triggers.empty())
    throw InputError(file + ": time model list_by: triggers, but the file has no list triggers (list_triggers: a " +
                     "version 4 workload, recorded on one rank with opencl-binned's list)");
  double work = 0, seconds = 0;
  for (int e = r.first_event; e < last; ++e) {
    const WorkloadEvent& ev = w.events[e];
    t.work.push_back(coarse(ev.slice_work, r.coarsen, t.slices));
    t.below.push_back(coarse_edges(ev.band_below, r.coarsen, t.slices));
    t.above.push_back(coarse_edges(ev.band_above, r.coarsen, t.slices));
    double sum = 0;
    for (double x : ev.slice_work) sum += x;
    t.per_element.push_back(ev.elements > 0 ? sum / static_cast<double>(ev.elements) : 0.0);
    t.phase.push_back(ev.growth_phase);
    t.growth.push_back(ev.growth_event);
    if (ev.interval_s > 0) work += sum, seconds += ev.interval_s;
    if (t.measured) {
      t.seconds.push_back(coarse(ev.slice_seconds, r.coarsen, t.slices));
      double total = 0;
      for (double x : ev.slice_seconds) total += x;
      t.seconds_per_element.push_back(ev.elements > 0 ? total / static_cast<double>(ev.elements) : 0.0);
      if (!ev.part_seconds.empty()) {  // the list builds leave the slices, where they were spread by elements
        const double list = ev.part_seconds[1], n = static_cast<double>(ev.elements);
        t.list_s.push_back(list);
        t.elements.push_back(coarse(ev.slice_elements, r.coarsen, t.slices));
        t.changes.push_back(coarse_bits(ev.cell_stage_changes, r.coarsen, t.slices));
        if (!ev.list_triggers.empty()) {
          t.builds.push_back(ev.list_builds);
          t.triggers.push_back(coarse_bits(ev.list_triggers, r.coarsen, t.slices));
        }
        auto sec = t.seconds.back();
        for (int s = 0; s < t.slices; ++s)
          sec[s] = std::max(0.0, sec[s] - (n > 0 ? list * t.elements.back()[s] / n : 0.0));
        t.without_list.push_back(std::move(sec));
      }
    }
  }
  t.seconds_per_work = r.model.seconds_per_work > 0 ? r.model.seconds_per_work : (work > 0 ? seconds / work : 1.0);
  return t;
}

std::vector<double> speed_factors(int ranks, uint64_t seed, double spread) {
  std::vector<double> s(ranks);
  for (int q = 0; q < ranks; ++q) s[q] = std::max(0.05, 1.0 + spread * rng::clipped_normal(seed, kSpeed, 0, q));
  return s;
}

std::vector<double> model_times(const ReplayTrack& t, int event, const std::vector<int>& b,
                                const std::vector<double>& speed, const TimeModel& m) {
  auto times = rank_sums(!t.list_s.empty() ? t.without_list[event] : t.measured ? t.seconds[event] : t.work[event], b);
  if (!t.list_s.empty()) {  // the list builds of the ranks whose slices changed (version 3)
    const auto& n = t.elements[event];
    const auto& bits = t.changes[event];
    const auto& work = t.work[event];
    int64_t any = 0;
    double total = 0, all_work = 0;
    for (int s = 0; s < t.slices; ++s) any |= bits[s], total += n[s], all_work += work[s];
    const int k = std::popcount(static_cast<uint64_t>(any));
    const bool by_triggers = m.list_by == TimeModel::ListBy::kTriggers;
    for (size_t q = 0; q < times.size(); ++q) {
      const int lo = q == 0 ? 0 : b[q - 1], hi = q + 1 < times.size() ? b[q] : t.slices;
      int64_t mine = 0, triggered = 0;
      double nq = 0, changed_work = 0, rank_work = 0;
      for (int s = lo; s < hi; ++s) {
        mine |= bits[s], nq += n[s], rank_work += work[s], changed_work += bits[s] != 0 ? work[s] : 0.0;
        if (by_triggers) triggered |= t.triggers[event][s];
      }
      const double by_elements = total > 0 ? t.list_s[event] * nq / total : 0.0;  // the list seconds by elements
      double list = 0;
      if (by_triggers) {  // the one rank's builds that r's triggers and stages claim, at r's share of W_s
        const long builds = t.builds[event];
        const long own = std::min<long>(
            builds, std::popcount(static_cast<uint64_t>(triggered)) + std::popcount(static_cast<uint64_t>(mine)));
        list = builds > 0 && all_work > 0
                   ? t.list_s[event] * static_cast<double>(own) / static_cast<double>(builds) * rank_work / all_work
                   : 0.0;
      } else if (m.list_by == TimeModel::ListBy::kWork) {
        list = all_work > 0 ? t.list_s[event] * changed_work / all_work : 0.0;
      } else {
        const double share = k > 0 ? static_cast<double>(std::popcount(static_cast<uint64_t>(mine))) / k : 1.0;
        list = by_elements * share;
      }
      times[q] += m.list_weight * list + m.list_element_weight * by_elements + m.element_s * nq;
    }
  }
  // seconds per unit of what `times` holds, and per received ghost element in those units
  const double scale = t.measured ? 1.0 : t.seconds_per_work;
  const double ghost = m.ghost_weight * (t.measured ? t.seconds_per_element[event] : t.per_element[event]);
  for (size_t q = 0; q < times.size(); ++q) {
    double g = 0;
    if (q > 0) g += t.below[event][b[q - 1] - 1];             // the rank below sends its elements below edge b_{q-1}
    if (q + 1 < times.size()) g += t.above[event][b[q] - 1];  // the rank above sends those above edge b_q
    times[q] = speed[q] * (scale * (times[q] + ghost * g) + m.rank_overhead_s);
  }
  return times;
}

WorkloadReplayResult replay_workload(const EngineWorkload& w, const WorkloadReplay& r, Policy& policy,
                                     const std::string& name, const std::string& file) {
  const ReplayTrack t = replay_track(w, r, file);
  const int K = static_cast<int>(t.work.size());
  const auto speed = speed_factors(r.ranks, r.seed, r.model.speed_spread);
  auto seconds_of = [&](int e) {  // per-slice seconds without ghosts or speed factors (oracle_work, foresight)
    if (t.measured) return t.seconds[e];
    auto v = t.work[e];
    for (double& x : v) x *= t.seconds_per_work;
    return v;
  };
  const auto initial = optimal_partition(t.work[0], r.ranks, t.min_width);
  WorkloadReplayResult res;
  res.events = K;
  res.slices = t.slices;
  res.measured = t.measured;
  double max_over_mean_sum = 0, decide_s = 0;
  auto account = [&](const std::vector<double>& times, long moved) {
    res.imbalance.push_back(global_imbalance(times));
    max_over_mean_sum += max_over_mean(times);
    const double mx = *std::max_element(times.begin(), times.end());
    double mean = 0;
    for (double x : times) mean += x / times.size();
    res.compute_s += mx;
    res.ideal_s += mean;
    res.migrate_s += r.model.migrate_s_per_slice * static_cast<double>(moved);
  };
  if (const auto* offline = dynamic_cast<const ForesightPolicy*>(&policy)) {
    std::vector<std::vector<double>> work;
    for (int e = 0; e < K; ++e) work.push_back(seconds_of(e));
    const auto start = std::chrono::steady_clock::now();
    const auto path = foresight_path(work, initial, t.min_width, offline->lambda());
    decide_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (int e = 0; e < K; ++e)
      account(model_times(t, e, path.boundaries[e], speed, r.model),
              e + 1 < K ? migration(path.boundaries[e], path.boundaries[e + 1]) : 0);
    res.migration = path.migration;
  } else {
    Balancer balancer(name, policy, t.slices, t.min_width, initial);
    for (int e = 0; e < K; ++e) {
      const auto truth = model_times(t, e, balancer.boundaries(), speed, r.model);
      Measurement m;
      m.times = noisy(truth, r.model.jitter, r.seed, kJitter, e);
      double total_t = 0, total_w = 0;
      for (double x : m.times) total_t += x;
      m.slice_work = t.work[e];
      for (double x : m.slice_work) total_w += x;
      for (double& x : m.slice_work)
        x *= total_w > 0 ? total_t / total_w : 0.0;  // W_s scaled to the times, as the engine does
      m.true_work = seconds_of(e + 1 < K ? e + 1 : e);
      m.growth_phase = t.phase[e];
      m.growth_event = t.growth[e];
      const long before = balancer.migration();
      try {
        decide_s += balancer.rebalance(std::move(m)).seconds;
      } catch (const ObservationError& err) {
        throw InputError(file + ": event " + std::to_string(r.first_event + e) + ": field '" + err.field +
                         "': " + err.what());
      } catch (const std::exception& err) {
        throw InputError(file + ": event " + std::to_string(r.first_event + e) + ": policy '" + name +
                         "': " + err.what());
      }
      account(truth, balancer.migration() - before);
    }
    res.migration = balancer.migration();
  }
  res.loop_s = res.compute_s + res.migrate_s;
  summarise(res, max_over_mean_sum);
  res.us_per_decision = 1e6 * decide_s / K;
  return res;
}

}  // namespace semlb::surrogate
