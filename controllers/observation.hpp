// The controller contract: what a policy sees at one rebalancing event (docs/design.md "The controller contract").
#pragma once
#include <string>
#include <vector>

#include "common/errors.hpp"

namespace semlb {

struct Observation {
  int event = 0;                    // rebalancing event index (0-based)
  int slices = 0;                   // number of slices along the partition axis
  int min_width = 1;                // minimum slices per rank (covers the ghost region)
  std::vector<int> boundaries;      // P-1 interior boundaries; rank r owns [b_{r-1}, b_r), b_{-1}=0, b_{P-1}=slices
  std::vector<double> times;        // measured per-rank computation times of the last interval (noisy)
  std::vector<double> slice_work;   // per-slice workload estimate (noisy); may be empty
  std::vector<double> oracle_work;  // noise-free per-slice work of the interval the decision governs; empty if unknown
  double growth_phase = 0.0;        // phase of the cell-growth cycle, in [0, 1)
  bool growth_event = false;        // a growth event happened during the last interval

  int ranks() const { return static_cast<int>(times.size()); }
};

// An InputError about one field of an Observation; `field` is the trace key ("times", "boundaries", ...), so
// that a trace reader can report "FILE:LINE: field 'times': ...".
struct ObservationError : InputError {
  ObservationError(std::string f, const std::string& message) : InputError(message), field(std::move(f)) {}
  std::string field;
};

// Checks every field (finite, non-negative times, valid partition, sizes); throws ObservationError naming the
// event and the field.
void validate(const Observation& obs);

// `v` (a field of obs named `field`, e.g. obs.slice_work) if non-empty; otherwise InputError
// "event E: policy 'POLICY' needs FIELD in the observation".
const std::vector<double>& require_field(const std::vector<double>& v, const Observation& obs, const char* policy,
                                         const char* field);

}  // namespace semlb
