// Engine workload files: the HDF5 layout (docs/controllers.md "Workload files"), strict reading, edge band counts.
#include "workload.hpp"

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"
#include "common/h5.hpp"
#include "common/text_io.hpp"

namespace semlb {
namespace {

constexpr const char* kFormat = "semlb-workload";
constexpr size_t kParts = 4;  // WorkloadEvent::part_seconds: pair forces, list builds, cell stage, the rest

[[noreturn]] void fail(const std::string& file, const std::string& field, const std::string& why) {
  throw InputError(file + ": field '" + field + "': " + why);
}

void check_counts(const std::vector<double>& v, size_t n, const std::string& file, const std::string& field,
                  long event) {
  if (v.size() != n)
    fail(file, field,
         "event " + std::to_string(event) + " has " + std::to_string(v.size()) + " entries, expected " +
             std::to_string(n));
  for (double x : v) {
    if (!(x >= 0) || x != std::floor(x))
      fail(file, field, "event " + std::to_string(event) + ": " + format_real(x) + " is not a non-negative integer");
    if (x > 9.0e15)  // beyond 2^53 doubles skip integers: sums of counts would no longer be exact
      fail(file, field,
           "event " + std::to_string(event) + ": " + format_real(x) +
               " exceeds 9e15, where counts stop being exact in doubles");
  }
}

// Measured seconds of one event: n finite non-negative entries summing to the event's interval_s (relative 1e-9).
void check_seconds(const std::vector<double>& v, size_t n, double interval_s, const std::string& file,
                   const std::string& field, long event) {
  const std::string at = "event " + std::to_string(event);
  if (v.size() != n)
    fail(file, field, at + " has " + std::to_string(v.size()) + " entries, expected " + std::to_string(n));
  double sum = 0;
  for (double x : v) {
    if (!(x >= 0) || !std::isfinite(x))
      fail(file, field, at + ": " + format_real(x) + " is not a finite non-negative number");
    sum += x;
  }
  if (std::abs(sum - interval_s) > 1e-9 * std::max(sum, interval_s))
    fail(file, field, at + ": sums to " + format_real(sum) + ", but interval_s is " + format_real(interval_s));
}

// Bit masks of one event, one per slice: n entries, none with a bit outside `allowed` (the sign bit never is); a
// failing mask M is reported as "event E: M WHY".
void check_masks(const std::vector<int64_t>& v, size_t n, int64_t allowed, const std::string& why,
                 const std::string& file, const std::string& field, long event) {
  const std::string at = "event " + std::to_string(event);
  if (v.size() != n)
    fail(file, field, at + " has " + std::to_string(v.size()) + " entries, expected " + std::to_string(n));
  for (int64_t m : v)
    if (m & ~allowed) fail(file, field, at + ": " + std::to_string(m) + " " + why);
}

}  // namespace

void validate_workload(const EngineWorkload& w, const std::string& file) {
  if (w.slices < 1) fail(file, "slices", "must be >= 1, got " + std::to_string(w.slices));
  if (w.min_width < 1 || w.min_width > w.slices)
    fail(file, "min_width", "must be in [1, slices], got " + std::to_string(w.min_width));
  if (!std::isfinite(w.x0_um)) fail(file, "x0_um", "must be finite");
  for (const auto& [name, v] : {std::pair<const char*, double>{"slice_width_um", w.slice_width_um},
                                {"cutoff_um", w.cutoff_um},
                                {"ghost_reach_um", w.ghost_reach_um}})
    if (!std::isfinite(v) || !(v > 0)) fail(file, name, "must be finite and > 0");
  if (w.rebalance_every < 1) fail(file, "rebalance_every", "must be >= 1");
  if (w.ranks < 1) fail(file, "ranks", "must be >= 1");
  if (w.events.empty()) fail(file, "events", "the workload has no events");
  if (w.cost_regions < 0 || w.cost_regions > w.slices)
    fail(file, "cost_regions", "must be in [0, slices], got " + std::to_string(w.cost_regions));
  const bool measured = !w.events.front().slice_seconds.empty();
  if (measured && w.cost_regions < 1) fail(file, "cost_regions", "must be >= 1 when the events carry slice_seconds");
  const bool parts = !w.events.front().part_seconds.empty();
  const bool triggers = !w.events.front().list_triggers.empty();
  for (const auto& e : w.events) {
    if (e.slice_seconds.empty() == measured) fail(file, "slice_seconds", "present at some events and not at others");
    if (e.part_seconds.empty() == parts) fail(file, "part_seconds", "present at some events and not at others");
    if (e.list_triggers.empty() == triggers) fail(file, "list_triggers", "present at some events and not at others");
  }
  if (parts && !measured) fail(file, "part_seconds", "present without slice_seconds");
  if (triggers && !parts) fail(file, "list_triggers", "present without part_seconds");
  const size_t S = static_cast<size_t>(w.slices);
  for (size_t t = 0; t < w.events.size(); ++t) {
    const WorkloadEvent& e = w.events[t];
    const long i = static_cast<long>(t);
    if (t > 0 && e.step <= w.events[t - 1].step)
      fail(file, "step", "event " + std::to_string(i) + ": steps must increase");
    if (e.step < 0) fail(file, "step", "event " + std::to_string(i) + ": negative");
    if (e.cells < 0 || e.elements < 0) fail(file, "cells", "event " + std::to_string(i) + ": negative count");
    if (!(e.growth_phase >= 0 && e.growth_phase < 1))
      fail(file, "growth_phase", "event " + std::to_string(i) + ": outside [0, 1)");
    if (!std::isfinite(e.time_h)) fail(file, "time_h", "event " + std::to_string(i) + ": not finite");
    if (!(e.interval_s >= 0) || !std::isfinite(e.interval_s))
      fail(file, "interval_s", "event " + std::to_string(i) + ": not a finite non-negative number");
    check_counts(e.slice_work, S, file, "slice_work", i);
    check_counts(e.slice_elements, S, file, "slice_elements", i);
    check_counts(e.band_below, S - 1, file, "band_below", i);
    check_counts(e.band_above, S - 1, file, "band_above", i);
    if (!e.slice_seconds.empty() || w.cost_regions > 0) {
      check_seconds(e.slice_seconds, S, e.interval_s, file, "slice_seconds", i);
    }
    if (parts) {
      check_seconds(e.part_seconds, kParts, e.interval_s, file, "part_seconds", i);
      check_masks(e.cell_stage_changes, S, INT64_MAX, "is negative (bits 0-62 only)", file, "cell_stage_changes", i);
    } else if (!e.cell_stage_changes.empty()) {
      fail(file, "cell_stage_changes", "event " + std::to_string(i) + ": present without part_seconds");
    }
    if (e.list_builds < 0) fail(file, "list_builds", "event " + std::to_string(i) + ": negative");
    if (triggers) {
      const int64_t allowed = e.list_builds >= 31 ? (int64_t{1} << 31) - 1 : (int64_t{1} << e.list_builds) - 1;
      check_masks(e.list_triggers, S, allowed,
                  "marks a build beyond the interval's " + std::to_string(e.list_builds) + " (bits 0-30 only)", file,
                  "list_triggers", i);
    } else if (e.list_builds != 0) {
      fail(file, "list_builds", "event " + std::to_string(i) + ": present without list_triggers");
    }
    double n = 0;
    for (double x : e.slice_elements) n += x;
    if (n != static_cast<double>(e.elements))
      fail(file, "slice_elements",
           "event " + std::to_string(i) + ": sums to " + std::to_string(static_cast<long>(n)) + ", but elements is " +
               std::to_string(e.elements));
    double work = 0;
    for (double x : e.slice_work) work += x;
    if ((e.elements == 0) != (work == 0))  // W_s = sum n_i n_N(i) >= 1 per element (paper eq. 2): both zero or neither
      fail(file, "slice_work",
           "event " + std::to_string(i) + ": sums to " + format_real(work) + " with " + std::to_string(e.elements) +
               " elements (each element adds at least 1)");
  }
  if (w.events.size() > 1 &&
      std::all_of(w.events.begin(), w.events.end(), [](const WorkloadEvent& e) { return e.interval_s == 0; }))
    fail(file, "interval_s", "every event's interval is 0 s: no measured time to turn work into seconds");
}

void write_workload(const std::string& path, const EngineWorkload& w) {
  validate_workload(w, path);
  h5::File::write_atomically(path, [&](h5::File& f) {  // a full disk: one line, no partial file
    f.set_deflate(6);
    f.write_attr("format", std::string(kFormat));
    const bool measured = has_measured_cost(w), parts = !w.events.front().part_seconds.empty();
    const bool triggers = !w.events.front().list_triggers.empty();
    f.write_attr("version", triggers ? 4L : parts ? 3L : measured ? 2L : 1L);
    if (measured) f.write_attr("cost_regions", static_cast<long>(w.cost_regions));
    f.write_attr("slices", static_cast<long>(w.slices));
    f.write_attr("min_width", static_cast<long>(w.min_width));
    f.write_attr("x0_um", w.x0_um);
    f.write_attr("slice_width_um", w.slice_width_um);
    f.write_attr("cutoff_um", w.cutoff_um);
    f.write_attr("ghost_reach_um", w.ghost_reach_um);
    f.write_attr("rebalance_every", w.rebalance_every);
    f.write_attr("ranks", static_cast<long>(w.ranks));
    f.write_attr("scene", w.scene);
    f.write_attr("command", w.command);
    f.write_attr("git_revision", w.git_revision);
    f.write_attr("device", w.device);
    const hsize_t E = w.events.size(), S = static_cast<hsize_t>(w.slices);
    std::vector<int64_t> step, cells, elements, event;
    std::vector<double> time, phase, interval;
    std::vector<int64_t> work, slice_elements, below, above;
    for (const auto& e : w.events) {
      step.push_back(e.step);
      cells.push_back(e.cells);
      elements.push_back(e.elements);
      event.push_back(e.growth_event ? 1 : 0);
      time.push_back(e.time_h);
      phase.push_back(e.growth_phase);
      interval.push_back(e.interval_s);
      for (double x : e.slice_work) work.push_back(static_cast<int64_t>(x));
      for (double x : e.slice_elements) slice_elements.push_back(static_cast<int64_t>(x));
      for (double x : e.band_below) below.push_back(static_cast<int64_t>(x));
      for (double x : e.band_above) above.push_back(static_cast<int64_t>(x));
    }
    f.write("events/step", {E}, step);
    f.write("events/time_h", {E}, time);
    f.write("events/cells", {E}, cells);
    f.write("events/elements", {E}, elements);
    f.write("events/growth_phase", {E}, phase);
    f.write("events/growth_event", {E}, event);
    f.write("events/interval_s", {E}, interval);
    f.write("events/slice_work", {E, S}, work);
    f.write("events/slice_elements", {E, S}, slice_elements);
    f.write("events/band_below", {E, S - 1}, below);
    f.write("events/band_above", {E, S - 1}, above);
    if (measured) {
      std::vector<double> seconds;
      for (const auto& e : w.events) seconds.insert(seconds.end(), e.slice_seconds.begin(), e.slice_seconds.end());
      f.write("events/slice_seconds", {E, S}, seconds);
    }
    if (parts) {
      std::vector<double> seconds;
      std::vector<int64_t> changes;
      for (const auto& e : w.events) {
        seconds.insert(seconds.end(), e.part_seconds.begin(), e.part_seconds.end());
        changes.insert(changes.end(), e.cell_stage_changes.begin(), e.cell_stage_changes.end());
      }
      f.write("events/part_seconds", {E, kParts}, seconds);
      f.write("events/cell_stage_changes", {E, S}, changes);
    }
    if (triggers) {
      std::vector<int64_t> builds, bits;
      for (const auto& e : w.events) {
        builds.push_back(e.list_builds);
        bits.insert(bits.end(), e.list_triggers.begin(), e.list_triggers.end());
      }
      f.write("events/list_builds", {E}, builds);
      f.write("events/list_triggers", {E, S}, bits);
    }
  });
}

EngineWorkload read_workload(const std::string& path) {
  const auto f = h5::File::open_read(path);
  std::string format;
  try {
    format = f.read_text_attr("format");
  } catch (const InputError&) {
    fail(path, "format", "missing (expected '" + std::string(kFormat) + "')");
  }
  if (format != kFormat) fail(path, "format", "is '" + format + "', expected '" + kFormat + "'");
  const long version = f.read_int_attr("version");
  if (version < 1 || version > EngineWorkload::kVersion)
    fail(
        path, "version",
        std::to_string(version) + " (this semlb reads versions 1 to " + std::to_string(EngineWorkload::kVersion) + ")");
  EngineWorkload w;
  auto integer_attr = [&](const char* name, long lo, long hi) {
    const long v = f.read_int_attr(name);
    if (v < lo || v > hi)
      fail(path, name, std::to_string(v) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  };
  w.slices = static_cast<int>(integer_attr("slices", 1, 1L << 24));
  w.min_width = static_cast<int>(integer_attr("min_width", 1, w.slices));
  w.rebalance_every = integer_attr("rebalance_every", 1, 1L << 40);
  w.ranks = static_cast<int>(integer_attr("ranks", 1, 1L << 20));
  w.x0_um = f.read_real_attr("x0_um");
  w.slice_width_um = f.read_real_attr("slice_width_um");
  w.cutoff_um = f.read_real_attr("cutoff_um");
  w.ghost_reach_um = f.read_real_attr("ghost_reach_um");
  w.scene = f.read_text_attr("scene");
  w.command = f.read_text_attr("command");
  w.git_revision = f.read_text_attr("git_revision");
  w.device = f.read_text_attr("device");
  std::vector<hsize_t> dims;
  auto series = [&](const std::string& name, bool integer) {
    const std::string key = "events/" + name;
    if (!f.has(key)) fail(path, name, "missing (dataset /" + key + ")");
    std::vector<double> v;
    if (integer) {
      const auto ints = f.read_ints(key, dims);
      v.assign(ints.begin(), ints.end());
    } else {
      v = f.read(key, dims);
    }
    return v;
  };
  const auto step = series("step", true);
  if (dims.size() != 1) fail(path, "step", "must be one-dimensional");
  const size_t E = dims[0], S = static_cast<size_t>(w.slices);
  // The last read dataset's shape must be [E] (cols 0) or [E, cols].
  auto shaped = [&](const std::string& name, size_t cols) {
    if (cols == 0 && (dims.size() != 1 || dims[0] != E))
      fail(path, name, "must hold one value per event (" + std::to_string(E) + ")");
    if (cols > 0 && (dims.size() != 2 || dims[0] != E || dims[1] != cols))
      fail(path, name,
           "must be events x " + std::to_string(cols) + " (" + std::to_string(E) + " x " + std::to_string(cols) + ")");
  };
  auto column = [&](const std::string& name, bool integer) {
    auto v = series(name, integer);
    shaped(name, 0);
    return v;
  };
  auto matrix = [&](const std::string& name, size_t cols, bool integer = true) {
    auto v = series(name, integer);
    shaped(name, cols);
    return v;
  };
  auto exact_ints = [&](const std::string& name, size_t cols) {  // bit masks: read as integers, not through doubles
    if (!f.has("events/" + name)) fail(path, name, "missing (dataset /events/" + name + ")");
    auto v = f.read_ints("events/" + name, dims);
    shaped(name, cols);
    return v;
  };
  const auto time = column("time_h", false), cells = column("cells", true), elements = column("elements", true);
  const auto phase = column("growth_phase", false), event = column("growth_event", true),
             interval = column("interval_s", false);
  const auto work = matrix("slice_work", S), slice_elements = matrix("slice_elements", S);
  const auto below = matrix("band_below", S - 1), above = matrix("band_above", S - 1);
  std::vector<double> seconds, parts;
  std::vector<int64_t> changes;
  if (version >= 2) {
    if (H5Aexists(f.id(), "cost_regions") <= 0)
      fail(path, "cost_regions", "missing (a version " + std::to_string(version) + " file holds measured seconds)");
    w.cost_regions = static_cast<int>(integer_attr("cost_regions", 1, w.slices));
    seconds = matrix("slice_seconds", S, false);
  }
  if (version >= 3) {
    parts = matrix("part_seconds", kParts, false);
    changes = exact_ints("cell_stage_changes", S);
  }
  std::vector<int64_t> builds, triggers;
  if (version == 4) {
    builds = exact_ints("list_builds", 0);
    triggers = exact_ints("list_triggers", S);
  }
  for (size_t t = 0; t < E; ++t) {
    WorkloadEvent e;
    e.step = static_cast<long>(step[t]);
    e.time_h = time[t];
    e.cells = static_cast<long>(cells[t]);
    e.elements = static_cast<long>(elements[t]);
    e.growth_phase = phase[t];
    if (event[t] != 0 && event[t] != 1) fail(path, "growth_event", "event " + std::to_string(t) + ": must be 0 or 1");
    e.growth_event = event[t] == 1;
    e.interval_s = interval[t];
    e.slice_work.assign(work.begin() + t * S, work.begin() + (t + 1) * S);
    e.slice_elements.assign(slice_elements.begin() + t * S, slice_elements.begin() + (t + 1) * S);
    e.band_below.assign(below.begin() + t * (S - 1), below.begin() + (t + 1) * (S - 1));
    e.band_above.assign(above.begin() + t * (S - 1), above.begin() + (t + 1) * (S - 1));
    if (!seconds.empty()) e.slice_seconds.assign(seconds.begin() + t * S, seconds.begin() + (t + 1) * S);
    if (!parts.empty()) {
      e.part_seconds.assign(parts.begin() + t * kParts, parts.begin() + (t + 1) * kParts);
      e.cell_stage_changes.assign(changes.begin() + t * S, changes.begin() + (t + 1) * S);
    }
    if (!triggers.empty()) {
      e.list_builds = static_cast<long>(builds[t]);
      e.list_triggers.assign(triggers.begin() + t * S, triggers.begin() + (t + 1) * S);
    }
    w.events.push_back(std::move(e));
  }
  validate_workload(w, path);
  return w;
}

bool has_measured_cost(const EngineWorkload& w) {
  return !w.events.empty() &&
         std::all_of(w.events.begin(), w.events.end(), [](const WorkloadEvent& e) { return !e.slice_seconds.empty(); });
}

void add_edge_bands(const std::vector<double>& x, double x0, double width, int slices, double reach,
                    std::vector<double>& below, std::vector<double>& above) {
  // Edge k (1..slices-1) lies at e_k = x0 + k width. An element at x is below edge k when e_k - reach <= x < e_k and
  // above it when e_k <= x < e_k + reach: two ranges of k, found from floor() and then corrected against e_k itself
  // (ties decide as the comparisons do), added as differences. O(elements + slices).
  std::vector<long> dlo(slices + 1, 0), dhi(slices + 1, 0);
  auto edge = [&](long k) { return x0 + static_cast<double>(k) * width; };
  auto index = [&](double v) {
    return static_cast<long>(std::clamp(std::floor((v - x0) / width), -2.0, slices + 2.0));
  };
  auto add = [&](std::vector<long>& d, long a, long b) {
    a = std::max(a, 1L);
    b = std::min(b, static_cast<long>(slices) - 1);
    if (a > b) return;
    ++d[a];
    --d[b + 1];
  };
  for (double xe : x) {
    if (!std::isfinite(xe)) continue;
    long first = index(xe) + 1, last = index(xe + reach);  // below: the edges in (x, x + reach]
    // Every correction stops at the edges that exist (add() clips to 1..slices-1 alike): an element far beyond the
    // last edge (x = 1e15 um) costs no loop over the edges it passed.
    while (first <= slices && edge(first) <= xe) ++first;
    while (first > 1 && edge(first - 1) > xe) --first;
    while (last < slices && edge(last + 1) - reach <= xe) ++last;
    while (last > 0 && edge(last) - reach > xe) --last;
    add(dlo, first, last);
    first = index(xe - reach) + 1, last = index(xe);  // above: the edges in (x - reach, x]
    while (first <= slices && edge(first) + reach <= xe) ++first;
    while (first > 1 && edge(first - 1) + reach > xe) --first;
    while (last < slices && edge(last + 1) <= xe) ++last;
    while (last > 0 && edge(last) > xe) --last;
    add(dhi, first, last);
  }
  long run_lo = 0, run_hi = 0;
  for (int k = 1; k < slices; ++k) {
    run_lo += dlo[k];
    run_hi += dhi[k];
    below[k - 1] += static_cast<double>(run_lo);
    above[k - 1] += static_cast<double>(run_hi);
  }
}

}  // namespace semlb
