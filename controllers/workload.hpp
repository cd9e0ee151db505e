// Engine workload files (HDF5, versioned; docs/controllers.md "Workload files"): the per-event workload of one run.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace semlb {

// One rebalancing event of an engine run, counted on the tissue as it is (no partition enters: W_s is counted on
// one grid over the whole tissue, so a run on 1 device and on P ranks records the same numbers).
struct WorkloadEvent {
  long step = 0;      // the event's step
  double time_h = 0;  // simulated time (h)
  long cells = 0, elements = 0;
  double growth_phase = 0;         // [0, 1): the growth cycle's phase (Observation::growth_phase)
  bool growth_event = false;       // cells were added since the previous event
  double interval_s = 0;           // measured computation seconds of the interval ending here, summed over the ranks
  std::vector<double> slice_work;  // [slices] W_s (paper eqs. 2-3), integer-valued
  std::vector<double> slice_elements;  // [slices] elements whose x lies in the slice
  // [slices - 1] per interior slice edge x_k = x0 + k width (k = 1..slices-1): the elements within ghost_reach_um
  // below it ([x_k - reach, x_k)) and above it ([x_k, x_k + reach)): the ghost bands a rank boundary at slice k
  // sends up and down (docs/engine.md "Decomposition").
  std::vector<double> band_below, band_above;
  // [slices] or empty: the measured device seconds of the interval ending here, per slice (version 2 files;
  // docs/measured_time.md "Measured workloads"): the step kernels' device time of every rank, the local pair forces
  // split over regions of the tissue by timed launches, each region's share over its slices by W_s, the rest of the
  // step kernels by elements. Sums to the interval's device seconds.
  std::vector<double> slice_seconds;
  // [4] or empty (version 3 files): the interval's device seconds by part (engine Backend::device_parts): the local
  // pair forces, the neighbour list's builds, the cell stage, the rest; summed over the ranks, so they sum to
  // interval_s.
  std::vector<double> part_seconds;
  // [slices] or empty (version 3 files): bit j (0 <= j < 63; the 63rd and later stages share bit 62) is set when the
  // slice's W_s changed at the interval's j-th cell stage: an element was added or removed within its reach, so a
  // rank holding the slice rebuilt its neighbour list then (a rank whose elements did not change keeps its list).
  std::vector<int64_t> cell_stage_changes;
  // Version 4 files (a recording on one rank whose backend keeps a neighbour list: opencl-binned with a skin; else
  // list_builds 0 and list_triggers empty): the list builds of the interval ending here, whatever started them, and
  // per slice [slices] bit j (0 <= j < 31; the 31st and later builds share bit 30) set when, at the interval's j-th
  // build, an element in the slice had moved past the list's displacement trigger, so a rank holding the slice would
  // have rebuilt then (engine Instruments::take_list_triggers).
  long list_builds = 0;
  std::vector<int64_t> list_triggers;
};

struct EngineWorkload {
  // 1: W_s only; 2: with the measured slice_seconds of every event (and cost_regions); 3: version 2 with the
  // part_seconds and cell_stage_changes of every event; 4: version 3 with the list_builds and list_triggers of every
  // event. All four are read.
  static constexpr long kVersion = 4;
  int cost_regions = 0;  // version 2: the regions the pair forces were timed over (0: no measured cost)
  int slices = 0, min_width = 1;
  double x0_um = 0, slice_width_um = 1, cutoff_um = 0, ghost_reach_um = 0;
  long rebalance_every = 0;                          // steps per event
  int ranks = 1;                                     // ranks of the recording run (the numbers do not depend on it)
  std::string scene, command, git_revision, device;  // where it came from (scene name, command line)
  std::vector<WorkloadEvent> events;
};

// Whether every event carries measured slice_seconds (the replay's truth is then measured, not W_s).
bool has_measured_cost(const EngineWorkload& w);
// Checks every invariant read_workload checks (shapes, integers, ranges, increasing steps); throws InputError
// "FILE: field 'NAME': reason" (FILE = `file`).
void validate_workload(const EngineWorkload& w, const std::string& file);
// Writes `w` to `path` atomically (h5::File::write_atomically), deflate-compressed; validates first.
// Version 4 when the events carry list_triggers (/events/list_builds, /events/list_triggers), 3 when they carry
// part_seconds (/events/part_seconds, /events/cell_stage_changes), version 2 (with /events/slice_seconds and the
// cost_regions attribute) when they carry measured seconds only, else 1.
void write_workload(const std::string& path, const EngineWorkload& w);
// Reads a workload file strictly: format "semlb-workload", version 1 to 4 (another is refused by name), every
// dataset present with its shape and type, then validate_workload. InputError "FILE: field 'NAME': reason".
EngineWorkload read_workload(const std::string& path);

// The interior-edge ghost counts of a set of elements' x (um): band_below/band_above as WorkloadEvent defines them,
// added into `below` and `above` ([slices - 1] each). O(elements + slices).
void add_edge_bands(const std::vector<double>& x, double x0, double width, int slices, double reach,
                    std::vector<double>& below, std::vector<double>& above);

}  // namespace semlb
