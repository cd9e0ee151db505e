// Experiment manifests (YAML): a runner, axes expanded as a cartesian product, fixed settings, profiles.
// Format: README.md "Manifest format".
#pragma once
#include <map>
#include <string>
#include <vector>

namespace semlb::experiments {

// One value with the manifest line it came from, or (line 0) the command-line flag that gave it ("--set ranks",
// "--ranks"): errors about the value name that source.
struct Setting {
  std::string value;
  long line = 0;
  std::string source;  // non-empty for values from the command line
};

// "SOURCE: " for a command-line value, else "MANIFEST:LINE: field 'KEY': ".
std::string where_of(const Setting& s, const std::string& manifest, const std::string& key);

// One row of a sweep: key -> value, in a fixed key order.
struct Job {
  std::vector<std::pair<std::string, Setting>> settings;
  const Setting* find(const std::string& key) const;
  // KEY parsed strictly (common/text_io.hpp) in [min, max]; FALLBACK when absent. Errors name the source.
  long integer(const std::string& key, long fallback, long min, long max, const std::string& manifest) const;
  double real(const std::string& key, double fallback, double min, double max, const std::string& manifest) const;
};

struct Manifest {
  std::string path, name, runner, output;
  std::vector<std::pair<std::string, std::vector<Setting>>> axes;  // in manifest order
  std::map<std::string, Setting> fixed;
  std::string profile;

  std::vector<Job> expand() const;  // last axis varies fastest; fixed settings follow the axes
  std::vector<std::string> axis_names() const;
};

// Loads FILE, applies the profile ("small" if the manifest has one and none is given), then `key=value`
// overrides (an axis key takes a comma list or an inclusive A-B range). Errors: "FILE:LINE: field 'x': ...".
Manifest load_manifest(const std::string& path, const std::string& profile,
                       const std::vector<std::string>& overrides);

}  // namespace semlb::experiments
