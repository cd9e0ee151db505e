// Validation of an Observation: every quantity a policy reads is checked once, here.
#include "observation.hpp"

#include <cmath>
#include <string>

#include "common/errors.hpp"
#include "partition.hpp"

namespace semlb {
namespace {

void check_values(const std::vector<double>& v, const char* name, int event) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]) || v[i] < 0.0)
      throw ObservationError(name, "event " + std::to_string(event) + ": " + name + "[" + std::to_string(i) +
                                       "] = " + std::to_string(v[i]) + " is not a finite non-negative number");
}

void check_size(const std::vector<double>& v, size_t expected, const char* name, int event) {
  if (!v.empty() && v.size() != expected)
    throw ObservationError(name, "event " + std::to_string(event) + ": " + name + " has " + std::to_string(v.size()) +
                                     " entries, expected " + std::to_string(expected) + " (one per slice)");
}

}  // namespace

void validate(const Observation& obs) {
  const std::string at = "event " + std::to_string(obs.event) + ": ";
  if (obs.times.empty()) throw ObservationError("times", at + "times is empty (need one time per rank)");
  if (obs.boundaries.size() + 1 != obs.times.size())
    throw ObservationError("boundaries", at + "boundaries has " + std::to_string(obs.boundaries.size()) +
                                             " entries but times has " + std::to_string(obs.times.size()) +
                                             " (need P-1 boundaries for P ranks)");
  if (obs.slices < 1) throw ObservationError("slices", at + "slices must be >= 1");
  try {
    check_partition(obs.boundaries, obs.slices, obs.min_width);
  } catch (const InputError& e) {
    throw ObservationError("boundaries", at + e.what());
  }
  check_values(obs.times, "times", obs.event);
  check_values(obs.slice_work, "slice_work", obs.event);
  check_values(obs.oracle_work, "oracle_work", obs.event);
  check_size(obs.slice_work, obs.slices, "slice_work", obs.event);
  check_size(obs.oracle_work, obs.slices, "oracle_work", obs.event);
  if (!std::isfinite(obs.growth_phase) || obs.growth_phase < 0.0 || obs.growth_phase > 1.0)
    throw ObservationError("growth_phase",
                           at + "growth_phase = " + std::to_string(obs.growth_phase) + " is not in [0, 1]");
}

const std::vector<double>& require_field(const std::vector<double>& v, const Observation& obs, const char* policy,
                                         const char* field) {
  if (v.empty())
    throw InputError("event " + std::to_string(obs.event) + ": policy '" + policy + "' needs " + field +
                     " in the observation");
  return v;
}

}  // namespace semlb
