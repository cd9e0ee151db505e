// Replay of a recorded engine workload at any rank count, with rank times as GPUs give them (docs/controllers.md
// "Replay of engine workloads").
#pragma once
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "controllers/policy.hpp"
#include "controllers/workload.hpp"
#include "rollout.hpp"

namespace semlb::surrogate {

// The per-rank time model. With W_r the W_s of rank r's slices, G_r the ghost elements it receives (band_above of the
// edge at its upper boundary, band_below of the edge at its lower one) and rho = sum W_s / elements of the event (work
// per element), the computation seconds of rank r in an interval are
//   T_r = s_r * c_w * (W_r + ghost_weight * rho * G_r),
// s_r = 1 + speed_spread * z_r (a fixed speed factor per rank, z_r standard normal clipped at 3 sigma, drawn once per
// replay seed), c_w = seconds per unit of W_s (from the workload's one-device interval_s, or seconds_per_work). A
// policy sees T_r (1 + jitter z) (fresh z per event and rank); the score uses the true T_r. The interval's loop time is
// max_r T_r plus migrate_s_per_slice per slice moved at its end. Constants fitted to measured multi-GPU runs: docs.
// Defaults: docs/controllers.md "Time model" (fit_time_model.py on results/gpu/engine_traces: the ghost weight is not
// identified by those runs and is set from the force loop's cost; jitter from the static run's residual; migration from
// the slope of migrate_s against slices moved at 435,661 cells).
//
// A workload with measured seconds (version 2, WorkloadEvent::slice_seconds; docs/measured_time.md) replaces the work
// by what the device took: with S_r the measured seconds of rank r's slices and sigma = sum of slice_seconds /
// elements (seconds per element of the event),
//   T_r = s_r * (S_r + ghost_weight * sigma * G_r + rank_overhead_s),
// while the policy still sees W_s (as on a machine). A version 3 file (WorkloadEvent::part_seconds and
// cell_stage_changes) places the neighbour list's builds where they happen: its list seconds L leave the slices
// (where they were spread by elements n_s) and rank r gets L n_r / N k_r / k, with k_r the cell stages at which one of
// its slices changed and k those at which any slice did (a rank whose elements did not change keeps its list); with
// list_by = work instead list_weight L Wch_r / W, Wch_r the W_s of r's slices that changed at some cell stage and W
// all W_s (a rebuild costs what the slices' pairs cost; docs/measured_time.md "Time model"); either placement is
// scaled by list_weight. With list_by = triggers (a version 4 file: WorkloadEvent::list_builds and list_triggers)
// rank r makes the builds at which one of its slices held an element past the list's trigger plus the cell stages at
// which one of its slices changed, b_r = popcount(OR of r's trigger bits) + popcount(OR of r's stage bits), capped at
// the one rank's k builds, each at its share of the one rank's build cost: list_weight L (b_r / k) (W_r / W), W_r the
// W_s of r's slices (a rebuild rebuilds the rank's whole list). A version 3 file also adds element_s n_r (the list
// check and sort launches of every step, per owned element) and list_element_weight L n_r / N (every slab rank
// rebuilds at about the one rank's rate, each on its own displacements: the list seconds by elements, beside the
// placed share; docs/measured_time.md "The time model on measured runs"). `truth` chooses: auto (measured when the file
// has it), work, or measured (an InputError for a file without it). rank_overhead_s (seconds per interval and rank: the
// fixed cost of a rank's launches) is added under either truth.
struct TimeModel {
  enum class Truth { kAuto, kWork, kMeasured };
  enum class ListBy { kStages, kWork, kTriggers };
  Truth truth = Truth::kAuto;
  ListBy list_by = ListBy::kStages;      // version 3: where the list builds' seconds go
  double list_weight = 1;                // version 3: the share of the one-rank list seconds the ranks' builds take
  double list_element_weight = 0;        // version 3: the share of them every rank takes by its elements
  double element_s = 0;                  // version 3: seconds per owned element and interval
  double rank_overhead_s = 0;            // seconds per interval and rank
  double ghost_weight = 0.5;             // a received ghost element's cost relative to an owned element's
  double speed_spread = 0.01;            // sigma of the per-rank speed factors
  double jitter = 0.03;                  // sigma of the measurement noise (relative)
  double migrate_s_per_slice = 1.24e-4;  // seconds per slice moved
  double seconds_per_work = 0;           // c_w; 0: sum(interval_s) / sum(W_s) over the workload's events
  std::set<std::string> given;           // the keys set_time_model set (replay_track refuses list keys that do nothing)
};

// The TimeModel keys ("ghost_weight", ...), and one "KEY=VALUE" set into `m` (strict numbers, each in its range:
// ghost_weight, list_weight and list_element_weight [0, 100], speed_spread and jitter [0, 0.3], migrate_s_per_slice,
// seconds_per_work and rank_overhead_s [0, 1e6], element_s [0, 1]; truth one of auto, work, measured; list_by one of
// stages, work, triggers). InputError prefixed by `where` naming the key. The key joins m.given.
const std::vector<std::string>& time_model_keys();
void set_time_model(TimeModel& m, const std::string& key, const std::string& value, const std::string& where);

// Replay settings: rank count, seed of the time model's draws, the events window [first_event, first_event + events)
// (events = 0: to the end), and `coarsen` adjacent slices merged into one (slices divisible by it is not required:
// the last slice takes the remainder).
struct WorkloadReplay {
  int ranks = 2;
  uint64_t seed = 0;
  int first_event = 0, events = 0;
  int coarsen = 1;
  TimeModel model;
};

struct WorkloadReplayResult : RolloutResult {
  int slices = 0;         // after coarsening
  double loop_s = 0;      // sum over intervals of max_r T_r + migration seconds (the projected loop time)
  double compute_s = 0;   // sum of max_r T_r
  double migrate_s = 0;   // migration seconds
  double ideal_s = 0;     // sum of mean_r T_r: a perfectly balanced loop
  bool measured = false;  // the truth was the workload's measured seconds (else W_s through the time model)
};

// The workload seen at `r.ranks` ranks after the window and coarsening: per event the slice work, and the per-edge
// ghost counts at the coarse edges. InputError (naming `file`, the field and the rank count) when the window is empty
// or P * min_width exceeds the slices.
struct ReplayTrack {
  int slices = 0, min_width = 1;
  std::vector<std::vector<double>> work, below, above;  // [events][slices], [events][slices - 1]
  std::vector<double> per_element;                      // rho per event (W_s per element)
  bool measured = false;                                // the truth is the file's measured seconds
  std::vector<std::vector<double>> seconds;             // [events][slices] measured seconds (when measured)
  // version 3: seconds without the list builds (model_times adds them per rank); the oracles and foresight see
  // `seconds`, additive over slices
  std::vector<std::vector<double>> without_list;
  std::vector<double> seconds_per_element;  // sigma per event (when measured)
  // version 3 files (else empty): per event the list builds' seconds, per slice its elements and its cell stages' bits
  std::vector<double> list_s;
  std::vector<std::vector<double>> elements;
  std::vector<std::vector<int64_t>> changes;
  // version 4 files (else empty): per event the one rank's list builds and per slice its trigger bits
  std::vector<long> builds;
  std::vector<std::vector<int64_t>> triggers;
  std::vector<double> phase;
  std::vector<bool> growth;
  double seconds_per_work = 0;
};
ReplayTrack replay_track(const EngineWorkload& w, const WorkloadReplay& r, const std::string& file);
// The true per-rank seconds of one event of `t` under `boundaries` (the time model above, without jitter).
std::vector<double> model_times(const ReplayTrack& t, int event, const std::vector<int>& boundaries,
                                const std::vector<double>& speed, const TimeModel& m);
// The speed factors s_r of a replay seed.
std::vector<double> speed_factors(int ranks, uint64_t seed, double spread);

// Event t: the interval runs under the boundaries in force (true times from the model, metrics from them), the policy
// sees the jittered times, W_s of the event scaled to their sum, and (oracle_work) the next event's modelled per-slice
// seconds; its decision governs interval t+1. Starts from the workload-aware optimal partition of event 0's W_s.
// A ForesightPolicy is solved offline on the modelled per-slice seconds of every event.
WorkloadReplayResult replay_workload(const EngineWorkload& w, const WorkloadReplay& r, Policy& policy,
                                     const std::string& name, const std::string& file);

}  // namespace semlb::surrogate
