// Sweep runners registered by name (a manifest's `runner:`): each turns one Job into CSV rows.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "manifest.hpp"

namespace semlb::experiments {

struct RunOptions {
  bool timing = true;     // false: wall-clock columns are written as 0 (byte-identical reruns)
  std::string trace_dir;  // non-empty: runners that produce traces write them here
  std::string base_dir;   // relative file paths in a manifest are relative to the manifest's folder
};

class Runner {
 public:
  virtual ~Runner() = default;
  virtual std::vector<std::string> columns() const = 0;
  // Throws InputError naming the manifest line/field of a bad or unknown setting; runs nothing.
  virtual void check(const Job& job, const std::string& manifest, const RunOptions& options) const = 0;
  // One or more rows (in columns() order); a job's rows are written together, so resume is per job.
  virtual std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& options) const = 0;
  // True when rows hold wall times that concurrent jobs would distort: the sweep then runs one at a time.
  virtual bool measures_time() const { return false; }
};

// Scene overrides ("tissue.cells=400") from a job: each job key in `keys` maps to its scene key, and a
// `scene.KEY` setting passes through as KEY. Shared by the engine runners.
std::vector<std::string> scene_overrides(const Job& job, const std::vector<std::pair<std::string, std::string>>& keys);

struct RunnerRegistrar {
  RunnerRegistrar(const std::string& name, std::function<std::unique_ptr<Runner>()> factory);
};

std::unique_ptr<Runner> make_runner(const std::string& name, const std::string& manifest);

}  // namespace semlb::experiments
