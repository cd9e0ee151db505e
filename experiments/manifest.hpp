// Experiment manifests (YAML): a runner, axes expanded as a cartesian product (or a union of products, one per
// axis group), fixed settings, profiles.
// Format: docs/experiments.md "Manifest format".
#pragma once
#include <map>
#include <string>
#include <vector>

#include "common/settings.hpp"

namespace semlb::experiments {

// One value with the manifest line it came from, or (line 0) the command-line flag that gave it ("--set ranks",
// "--ranks"): errors about the value name that source.
struct Setting {
  std::string value;
  long line = 0;
  std::string source;  // non-empty for values from the command line
};

// Where S came from, as semlb::Origin (common/settings.hpp): MANIFEST's line, or the flag.
Origin origin_of(const Setting& s, const std::string& manifest);
// "SOURCE: " for a command-line value, else "MANIFEST:LINE: field 'KEY': " (semlb::where(origin_of(s), key)).
std::string where_of(const Setting& s, const std::string& manifest, const std::string& key);

// One row of a sweep: key -> value, in a fixed key order.
struct Job {
  std::vector<std::pair<std::string, Setting>> settings;
  const Setting* find(const std::string& key) const;
  // The row as a semlb::Settings, in key order, each value blamed on its manifest line or flag.
  Settings reader(const std::string& manifest) const;
  // KEY's value as written, or FALLBACK when the job does not set KEY.
  std::string text(const std::string& key, const std::string& fallback) const;
  // KEY parsed strictly (Settings::integer / real) in [min, max]; FALLBACK when absent. Errors name the source.
  long integer(const std::string& key, long fallback, long min, long max, const std::string& manifest) const;
  double real(const std::string& key, double fallback, double min, double max, const std::string& manifest) const;
};

using Axes = std::vector<std::pair<std::string, std::vector<Setting>>>;  // in manifest order

struct Manifest {
  std::string path, name, runner, output;
  Axes axes;                 // shared by every row
  std::vector<Axes> groups;  // `groups:`: each adds the product of its own axes with the shared ones
  std::map<std::string, Setting> fixed;
  std::string profile;
  // `launches: N` (N >= 1): every row N times, launch-major (launch 1 of every row, then launch 2, ...), each
  // with a `launch` axis 1..N, so that machine drift over a sweep falls on every row alike. 0: no launch axis.
  long launches = 0;
  Setting launches_at;  // where `launches` was given (errors about a row's `launch` name it)

  // Without groups: the product of the axes, last axis fastest. With groups: for each group in order, the
  // product of the group's axes (outer) and the shared axes; a row lacks the axes of the other groups.
  // Fixed settings follow the axes. With `launches`, the whole list repeats once per launch, `launch` first.
  std::vector<Job> expand() const;
  // `launch` (with launches), the shared axes, then each group's new ones, first seen first
  std::vector<std::string> axis_names() const;
};

// Loads FILE, applies the profile ("small" if the manifest has one and none is given), then `key=value`
// overrides (an axis key takes a comma list or an inclusive A-B range). Errors: "FILE:LINE: field 'x': ...".
Manifest load_manifest(const std::string& path, const std::string& profile, const std::vector<std::string>& overrides);

}  // namespace semlb::experiments
