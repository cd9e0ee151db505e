// Engine runners: "engine_timing" (single_device, effects_cost: wall time of a scene per backend, size
// and effect set) and "engine_accuracy" (accuracy_vs_time: error against a reference run vs wall time).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "engine/run/bench.hpp"
#include "engine/run/simulation.hpp"
#include "engine/model/tissue.hpp"
#include "runner.hpp"

namespace semlb::experiments {
namespace {

std::string value(const Job& job, const std::string& key, const std::string& fallback) {
  const Setting* s = job.find(key);
  return s ? s->value : fallback;
}

std::string fmt(double v) { return format_real(v); }  // round-trip text (common/text_io.hpp)

// The scene settings (engine::scene_settings()) these runners take by name; `steps` is theirs (timed steps).
const std::vector<std::string> kSceneNames = {"cells", "backend", "precision", "platform", "dt", "cutoff"};

// The job's scene: `scene` (relative to the manifest), the kSceneNames settings, `scene.KEY` overrides;
// `effects` ("a+b+c" or "all") keeps only those listed.
engine::Scene job_scene(const Job& job, const std::string& manifest, const std::string& base_dir) {
  const Setting* file = job.find("scene");
  if (!file) throw InputError(where(manifest, 0, "scene") + "missing (engine runners need a scene file)");
  const std::string path = std::filesystem::path(file->value).is_absolute() ? file->value : base_dir + "/" + file->value;
  const auto o = scene_overrides(job, kSceneNames, manifest);
  engine::Scene scene;
  try {
    scene = engine::load_scene(path, o);
  } catch (const InputError& e) {
    throw InputError(where_of(*file, manifest, "scene") + e.what());
  }
  const std::string effects = value(job, "effects", "all");
  if (effects != "all") {
    const auto keep = split(effects, '+');
    for (const auto& k : keep) {
      bool found = false;
      for (const auto& [name, section] : scene.effects) found = found || name == k;
      if (!found) throw InputError(where_of(*job.find("effects"), manifest, "effects") + "'" + k + "' is not an effect of " + path);
    }
    std::erase_if(scene.effects, [&](const auto& e) { return std::find(keep.begin(), keep.end(), e.first) == keep.end(); });
  }
  return scene;
}

long integer(const Job& job, const std::string& key, long fallback, const std::string& manifest) {
  return job.integer(key, fallback, 0, std::numeric_limits<long>::max(), manifest);
}

// Refuses a setting that is neither one of kSceneNames, nor `known` (the runner's own), nor scene.KEY / max_cells.KEY.
void check_keys(const Job& job, const std::string& manifest, const std::vector<std::string>& known) {
  auto listed = [](const std::vector<std::string>& v, const std::string& k) { return std::find(v.begin(), v.end(), k) != v.end(); };
  for (const auto& [k, s] : job.settings)
    if (!listed(known, k) && !listed(kSceneNames, k) && k.rfind("scene.", 0) != 0 && k.rfind("max_cells.", 0) != 0)
      throw InputError(where_of(s, manifest, k) + "unknown setting for this runner");
  for (const auto& [k, s] : job.settings)  // max_cells.BACKEND: the largest cell count BACKEND is timed at
    if (k.rfind("max_cells.", 0) == 0) integer(job, k, 0, manifest);
}

class TimingRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override {
    return {"backend", "precision", "effects", "cells", "elements", "steps", "seconds", "s_per_1000_steps",
            "element_steps_per_s", "per_cutoff_cube", "candidates", "neighbours", "phases", "device"};
  }
  bool measures_time() const override { return true; }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_keys(job, manifest, {"scene", "effects", "steps", "warmup"});
    auto scene = job_scene(job, manifest, o.base_dir);
    engine::make_effects(scene);  // parameters checked now, not an hour into the sweep
    integer(job, "steps", 100, manifest);
    integer(job, "warmup", 2, manifest);
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    auto scene = job_scene(job, "", o.base_dir);
    const long steps = integer(job, "steps", 100, ""), warmup = integer(job, "warmup", 2, "");
    std::vector<std::string> row = {scene.backend.name, scene.backend.precision, value(job, "effects", "all"), value(job, "cells", "")};
    const std::string limit = value(job, "max_cells." + scene.backend.name, "");
    if (!limit.empty() && integer(job, "cells", 0, "") > integer(job, "max_cells." + scene.backend.name, 0, "")) {  // e.g. serial all-pairs at large n
      row.insert(row.end(), {"", std::to_string(steps), "", "", "", "", "", "", "", "skipped: above max_cells." + scene.backend.name});
      return {row};
    }
    const auto t = engine::time_scene(scene, steps, warmup, o.timing ? steps : 0);
    const auto& stats = t.stats;
    std::string phases;
    for (size_t p = 0; p < t.phase_seconds.size(); ++p) phases += (p ? ";" : "") + t.phases[p] + "=" + fmt(t.phase_seconds[p]);
    const double secs = o.timing ? t.seconds : 0;
    row.insert(row.end(), {std::to_string(t.elements), std::to_string(steps), fmt(secs), fmt(secs / steps * 1000),
                           fmt(o.timing ? t.element_steps_per_second() : 0), fmt(stats.per_cutoff_cube), fmt(stats.candidates),
                           fmt(stats.neighbours), phases, o.timing ? t.device : ""});
    return {row};
  }
};

// Final positions of a run of `hours` simulated time; the wall time of the stepping alone.
engine::State run_for(engine::Scene scene, double hours, double& wall) {
  engine::Simulation sim(scene, engine::make_tissue(scene));
  const long steps = std::lround(hours / scene.dt);
  sim.profile = false;
  const auto t0 = std::chrono::steady_clock::now();
  sim.advance(steps);
  sim.backend().finish();
  wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sim.sync();
}

class AccuracyRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override {
    return {"precision", "dt", "cutoff", "steps", "wall_s", "rms_error_um", "max_error_um", "reference"};
  }
  bool measures_time() const override { return true; }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_keys(job, manifest, {"scene", "effects", "hours", "reference_dt", "reference_cutoff"});
    auto scene = job_scene(job, manifest, o.base_dir);
    engine::make_effects(scene);
    for (const auto& e : scene.effects)
      if (e.first == "growth" || e.first == "division" || e.first == "noise")
        throw InputError((job.find("effects") ? where_of(*job.find("effects"), manifest, "effects") : where(manifest, 0, "effects")) +
                         "accuracy runs compare element by element: leave out " + e.first);
    job.real("hours", 2.0, 1e-9, 1e9, manifest);
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const auto scene = job_scene(job, "", o.base_dir);
    const double hours = job.real("hours", 2.0, 1e-9, 1e9, "");
    double wall = 0, unused = 0;
    const auto state = run_for(scene, hours, wall);
    const auto& ref = reference(job, o, hours, unused);
    double sum = 0, worst = 0;
    for (size_t i = 0; i < ref.position.size(); i += 3) {
      double d2 = 0;
      for (int d = 0; d < 3; ++d) d2 += std::pow(state.position[i + d] - ref.position[i + d], 2);
      sum += d2;
      worst = std::max(worst, std::sqrt(d2));
    }
    const double rms = std::sqrt(sum / std::max<size_t>(1, ref.position.size() / 3));
    return {{scene.backend.precision, value(job, "dt", fmt(scene.dt)), value(job, "cutoff", fmt(scene.cutoff)),
             std::to_string(std::lround(hours / scene.dt)), fmt(o.timing ? wall : 0), fmt(rms), fmt(worst),
             "dt=" + value(job, "reference_dt", "?") + " double cutoff=" + value(job, "reference_cutoff", fmt(scene.cutoff))}};
  }

 private:
  // The reference (smallest time step, double precision) is computed once per process and setting.
  const engine::State& reference(const Job& job, const RunOptions& o, double hours, double& wall) const {
    Job ref = job;
    for (auto& [k, s] : ref.settings) {
      if (k == "precision") s.value = "double";
      if (k == "dt") s.value = value(job, "reference_dt", s.value);
      if (k == "cutoff") s.value = value(job, "reference_cutoff", s.value);
    }
    std::string key;
    for (const auto& [k, s] : ref.settings) key += k + "=" + s.value + ";";
    std::lock_guard lock(mutex_);
    auto it = cache_.find(key);
    if (it == cache_.end()) it = cache_.emplace(key, run_for(job_scene(ref, "", o.base_dir), hours, wall)).first;
    return it->second;
  }
  mutable std::mutex mutex_;
  mutable std::map<std::string, engine::State> cache_;
};

const RunnerRegistrar timing("engine_timing", [] { return std::make_unique<TimingRunner>(); });
const RunnerRegistrar accuracy("engine_accuracy", [] { return std::make_unique<AccuracyRunner>(); });

}  // namespace
}  // namespace semlb::experiments
