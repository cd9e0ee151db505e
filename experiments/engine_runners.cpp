// Engine runners: "engine_timing" (single_device, effects_cost: wall time of a scene per backend, size
// and effect set), "engine_accuracy" (accuracy_vs_time: position error against a reference run vs wall time) and
// "engine_observables" (accuracy_development: cells per type, thickness and work profile against a reference run).
#include <algorithm>
#include <array>
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
#include "engine/decomposition/decomposition.hpp"
#include "engine/simulation/simulation.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "runner.hpp"

namespace semlb::experiments {
namespace {

std::string fmt(double v) { return format_real(v); }  // round-trip text (common/text_io.hpp)

// The scene settings (engine::scene_settings()) these runners take by name; `steps` is theirs (timed steps).
const std::vector<std::string> kSceneNames = {"cells", "backend", "precision", "platform", "pair_exp", "dt", "cutoff"};

// The job's scene (job_scene with kSceneNames); `effects` ("a+b+c" or "all") keeps only those listed.
engine::Scene engine_scene(const Job& job, const std::string& manifest, const std::string& base_dir) {
  engine::Scene scene = job_scene(job, kSceneNames, manifest, base_dir);
  const std::string effects = job.text("effects", "all");
  if (effects != "all") {
    const auto keep = split(effects, '+');
    for (const auto& k : keep) {
      bool found = false;
      for (const auto& [name, section] : scene.effects) found = found || name == k;
      if (!found)
        throw InputError(where_of(*job.find("effects"), manifest, "effects") + "'" + k + "' is not an effect of " +
                         resolve_path(base_dir, job.find("scene")->value));
    }
    std::erase_if(scene.effects,
                  [&](const auto& e) { return std::find(keep.begin(), keep.end(), e.first) == keep.end(); });
  }
  return scene;
}

long integer(const Job& job, const std::string& key, long fallback, const std::string& manifest) {
  return job.integer(key, fallback, 0, std::numeric_limits<long>::max(), manifest);
}

// Refuses a setting that is neither one of kSceneNames, nor `known` (the runner's own), nor scene.KEY / max_cells.KEY.
void check_keys(const Job& job, const std::string& manifest, std::vector<std::string> known) {
  known.insert(known.end(), kSceneNames.begin(), kSceneNames.end());
  check_settings(
      job, manifest, known,
      [](const std::string& k) { return k.rfind("scene.", 0) == 0 || k.rfind("max_cells.", 0) == 0; }, "this runner");
  for (const auto& [k, s] : job.settings)  // max_cells.BACKEND: the largest cell count BACKEND is timed at
    if (k.rfind("max_cells.", 0) == 0) integer(job, k, 0, manifest);
}

class TimingRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override {
    return {
        "backend",          "precision",           "effects",         "cells",      "elements",   "steps",  "seconds",
        "s_per_1000_steps", "element_steps_per_s", "per_cutoff_cube", "candidates", "neighbours", "phases", "device"};
  }
  bool measures_time() const override { return true; }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_keys(job, manifest, {"scene", "effects", "steps", "warmup"});
    auto scene = engine_scene(job, manifest, o.base_dir);
    engine::make_effects(scene);  // parameters checked now, not an hour into the sweep
    integer(job, "steps", 100, manifest);
    integer(job, "warmup", 2, manifest);
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    auto scene = engine_scene(job, "", o.base_dir);
    const long steps = integer(job, "steps", 100, ""), warmup = integer(job, "warmup", 2, "");
    std::vector<std::string> row = {scene.backend.name, scene.backend.precision, job.text("effects", "all"),
                                    job.text("cells", "")};
    const std::string limit = job.text("max_cells." + scene.backend.name, "");
    if (!limit.empty() && integer(job, "cells", 0, "") > integer(job, "max_cells." + scene.backend.name, 0,
                                                                 "")) {  // e.g. serial all-pairs at large n
      row.insert(row.end(), {"", std::to_string(steps), "", "", "", "", "", "", "",
                             "skipped: above max_cells." + scene.backend.name});
      return {row};
    }
    const auto t = engine::time_scene(scene, steps, warmup, o.timing ? steps : 0);
    const auto& stats = t.stats;
    std::string phases;
    for (size_t p = 0; p < t.phase_seconds.size(); ++p)
      phases += (p ? ";" : "") + t.phases[p] + "=" + fmt(t.phase_seconds[p]);
    const double secs = o.timing ? t.seconds : 0;
    row.insert(row.end(), {std::to_string(t.elements), std::to_string(steps), fmt(secs), fmt(secs / steps * 1000),
                           fmt(o.timing ? t.element_steps_per_second() : 0), fmt(stats.per_cutoff_cube),
                           fmt(stats.candidates), fmt(stats.neighbours), phases, o.timing ? t.device : ""});
    return {row};
  }
};

constexpr const char* kReferenceExp = "builtin";  // the reference run's pair exp (backend.pair_exp)

// Whether `key` sets the OpenCL backends' pair_exp: the named setting, or scene.backend[.NAME].pair_exp.
bool sets_pair_exp(const std::string& key) {
  return key == "pair_exp" ||
         (key.rfind("scene.backend.", 0) == 0 && key.size() > 9 && key.compare(key.size() - 9, 9, ".pair_exp") == 0);
}

// The job's reference run: its settings with precision double, dt = reference_dt and cutoff = reference_cutoff
// (where given) and the builtin pair exp, in whichever form the job sets each: the named setting or scene.KEY (a
// GPU script's scene.backend.precision must not make the reference float too); a precision, dt or cutoff the job
// does not set is added by name.
Job reference_job(const Job& job) {
  Job ref = job;
  std::vector<std::pair<std::string, std::string>> want = {{"precision", "double"}};
  if (const Setting* s = job.find("reference_dt")) want.emplace_back("dt", s->value);
  if (const Setting* s = job.find("reference_cutoff")) want.emplace_back("cutoff", s->value);
  for (const auto& [name, value] : want) {
    const std::string key = std::string("scene.") + engine::scene_setting(name).key;
    bool set = false;
    for (auto& [k, s] : ref.settings)
      if (k == name || k == key) s.value = value, set = true;
    if (!set) ref.settings.push_back({name, Setting{value, 0, ""}});
  }
  for (auto& [k, s] : ref.settings)
    if (sets_pair_exp(k)) s.value = kReferenceExp;
  return ref;
}

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
    auto scene = engine_scene(job, manifest, o.base_dir);
    engine::make_effects(scene);
    for (const auto& e : scene.effects)
      if (e.first == "growth" || e.first == "division" || e.first == "noise")
        throw InputError((job.find("effects") ? where_of(*job.find("effects"), manifest, "effects")
                                              : where(manifest, 0, "effects")) +
                         "accuracy runs compare element by element: leave out " + e.first);
    job.real("hours", 2.0, 1e-9, 1e9, manifest);
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const auto scene = engine_scene(job, "", o.base_dir);
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
    return {{scene.backend.precision, job.text("dt", fmt(scene.dt)), job.text("cutoff", fmt(scene.cutoff)),
             std::to_string(std::lround(hours / scene.dt)), fmt(o.timing ? wall : 0), fmt(rms), fmt(worst),
             "dt=" + job.text("reference_dt", "?") +
                 " double cutoff=" + job.text("reference_cutoff", fmt(scene.cutoff)) +
                 (std::any_of(job.settings.begin(), job.settings.end(),
                              [](const auto& kv) { return sets_pair_exp(kv.first); })
                      ? std::string(" pair_exp=") + kReferenceExp
                      : std::string())}};
  }

 private:
  // The reference (smallest time step, double precision) is computed once per process and setting.
  const engine::State& reference(const Job& job, const RunOptions& o, double hours, double& wall) const {
    const Job ref = reference_job(job);
    const std::string key = job_key(ref);
    std::lock_guard lock(mutex_);
    auto it = cache_.find(key);
    if (it == cache_.end()) it = cache_.emplace(key, run_for(engine_scene(ref, "", o.base_dir), hours, wall)).first;
    return it->second;
  }
  mutable std::mutex mutex_;
  mutable std::map<std::string, engine::State> cache_;
};

// What a user reads off a development run at one time point (engine_observables): cells per type, the tissue's
// thickness (z extent of its elements, um), the per-slice work W_s the controllers see (shares of the total over
// the reference's slices, and their centre along x, um), and the stepping's wall seconds so far.
struct Observables {
  long step = 0, cells = 0;
  std::array<long, engine::kCellTypes> per_type{};
  double thickness_um = 0, work_centre_um = 0, wall_s = 0;
  std::vector<double> work_share;
};

Observables observe(const engine::State& s, const engine::SliceMap& map, double cutoff, double wall) {
  Observables ob;
  ob.step = s.step;
  ob.cells = s.cells();
  ob.wall_s = wall;
  for (int t : s.cell_type) ++ob.per_type.at(static_cast<size_t>(t));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t i = 2; i < s.position.size(); i += 3) lo = std::min(lo, s.position[i]), hi = std::max(hi, s.position[i]);
  ob.thickness_um = s.position.empty() ? 0.0 : hi - lo;
  ob.work_share = engine::slice_workload(s, map, cutoff);
  double total = 0, moment = 0;
  for (size_t k = 0; k < ob.work_share.size(); ++k) {
    total += ob.work_share[k];
    moment += ob.work_share[k] * (map.x0 + (static_cast<double>(k) + 0.5) * map.width);
  }
  for (double& w : ob.work_share) w = total > 0 ? w / total : 0.0;
  ob.work_centre_um = total > 0 ? moment / total : 0.0;
  return ob;
}

// Runs `scene` from its tissue for `samples` x `every` steps, observing the state at step 0 and after every `every`
// steps; wall_s counts the stepping alone (cumulative), not the observing.
std::vector<Observables> observe_run(const engine::Scene& scene, long samples, long every,
                                     const engine::SliceMap& map) {
  engine::Scene sc = scene;
  engine::Simulation sim(sc, engine::make_tissue(sc));
  sim.profile = false;
  std::vector<Observables> out = {observe(sim.sync(), map, sc.cutoff, 0.0)};
  double wall = 0;
  for (long k = 1; k <= samples; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    sim.advance(k * every);
    sim.backend().finish();
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.push_back(observe(sim.sync(), map, sc.cutoff, wall));
  }
  return out;
}

// Accuracy on what a biologist reads, for scenes whose cells grow, divide and differentiate (so runs cannot be compared
// element by element): each row is one run (precision, dt, cutoff) at one sample time (every `sample_h` hours
// over `hours`), beside the reference run (reference_dt, double, reference_cutoff) at the same time. The cell stage
// runs every `cell_stage_h` hours (required) whatever dt (time.cell_update_every = cell_stage_h / dt). Each run, the
// reference included, is computed once per process. Errors: cells_error = sum over types |n - n_ref| / cells_ref;
// work_profile_error = half the L1 distance of the W_s shares (the share of the work in other slices than the
// reference's); thickness and work centre as differences (um).
class ObservablesRunner final : public Runner {
 public:
  // cells per type: one column per type, named engine::type_name (`semlb list cell-types`), by type index
  std::vector<std::string> columns() const override {
    std::vector<std::string> c = {"precision", "dt", "cutoff", "time_h", "steps", "wall_s", "cells"};
    for (int t = 0; t < engine::kCellTypes; ++t) c.push_back(engine::type_name(t));
    c.insert(c.end(), {"thickness_um", "work_centre_um", "cells_error", "thickness_error_um", "work_centre_error_um",
                       "work_profile_error", "reference"});
    return c;
  }
  bool measures_time() const override { return true; }
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_keys(job, manifest, {"scene", "hours", "sample_h", "cell_stage_h", "reference_dt", "reference_cutoff"});
    for (const char* k : {"reference_dt", "reference_cutoff"}) job.real(k, 1, 1e-9, 1e9, manifest);
    for (const Job& j : {job, reference_job(job)}) {
      auto scene = engine_scene(j, manifest, o.base_dir);
      engine::make_effects(scene);
      plan(j, scene, manifest);
    }
  }
  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const auto& mine = observations(job, o);
    const auto& ref = observations(reference_job(job), o);
    const engine::Scene scene = engine_scene(job, "", o.base_dir);
    std::vector<std::vector<std::string>> rows;
    for (size_t k = 0; k < mine.size(); ++k) {
      const Observables &a = mine[k], &b = ref.at(k);
      double type_diff = 0, profile_diff = 0;
      for (size_t t = 0; t < a.per_type.size(); ++t)
        type_diff += std::abs(static_cast<double>(a.per_type[t] - b.per_type[t]));
      for (size_t s = 0; s < a.work_share.size(); ++s) profile_diff += std::abs(a.work_share[s] - b.work_share.at(s));
      std::vector<std::string> row = {scene.backend.precision,
                                      job.text("dt", fmt(scene.dt)),
                                      job.text("cutoff", fmt(scene.cutoff)),
                                      fmt(static_cast<double>(a.step) * scene.dt),
                                      std::to_string(a.step),
                                      fmt(o.timing ? a.wall_s : 0),
                                      std::to_string(a.cells)};
      for (long n : a.per_type) row.push_back(std::to_string(n));
      row.insert(
          row.end(),
          {fmt(a.thickness_um), fmt(a.work_centre_um), fmt(type_diff / static_cast<double>(std::max(1L, b.cells))),
           fmt(a.thickness_um - b.thickness_um), fmt(a.work_centre_um - b.work_centre_um), fmt(profile_diff / 2),
           "dt=" + job.text("reference_dt", "?") +
               " double cutoff=" + job.text("reference_cutoff", fmt(scene.cutoff))});
      rows.push_back(std::move(row));
    }
    return rows;
  }

 private:
  // The job's samples and steps per sample, with its scene's cell stage set to every cell_stage_h hours; InputError
  // (naming the field) when hours, sample_h or cell_stage_h is not a whole number of the job's steps.
  static std::pair<long, long> plan(const Job& job, engine::Scene& scene, const std::string& manifest) {
    const double hours = job.real("hours", 120.0, 1e-9, 1e9, manifest),
                 sample = job.real("sample_h", 24.0, 1e-9, 1e9, manifest);
    if (!job.find("cell_stage_h"))
      throw InputError(where(manifest, 0, "cell_stage_h") +
                       "missing (the cell stage's period in hours, the same for every dt)");
    const double stage = job.real("cell_stage_h", 0.5, 1e-9, 1e9, manifest);
    auto whole = [&](const char* key, double v, double of, const std::string& unit) {
      const double n = v / of;
      if (std::abs(n - std::round(n)) > 1e-9 * n || std::round(n) < 1) {
        const Setting* s = job.find(key);
        throw InputError((s ? where_of(*s, manifest, key) : where(manifest, 0, key)) + fmt(v) +
                         " h is not a whole number of " + unit + " of " + fmt(of) + " h");
      }
      return std::lround(n);
    };
    scene.cell_update_every = whole("cell_stage_h", stage, scene.dt, "steps (dt)");
    const long every = whole("sample_h", sample, scene.dt, "steps (dt)");
    return {whole("hours", hours, sample, "samples (sample_h)"), every};
  }
  // The observations of the job's run over the reference's slices (Decomposition::from_scene of the reference
  // scene, its box fitted to the initial tissue at the reference cutoff), computed once per process and setting.
  const std::vector<Observables>& observations(const Job& job, const RunOptions& o) const {
    const std::string key = job_key(job);
    {
      std::lock_guard lock(mutex_);
      if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    }
    engine::Scene ref = engine_scene(reference_job(job), "", o.base_dir);
    engine::make_tissue(ref);  // fits the box
    const engine::SliceMap map = engine::Decomposition::from_scene(ref, 1);
    engine::Scene scene = engine_scene(job, "", o.base_dir);
    const auto [samples, every] = plan(job, scene, "");
    auto obs = observe_run(scene, samples, every, map);
    std::lock_guard lock(mutex_);
    return cache_.emplace(key, std::move(obs)).first->second;
  }
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::vector<Observables>> cache_;
};

const Registrar<RunnerInfo> timing("engine_timing", {[] { return std::make_unique<TimingRunner>(); }});
const Registrar<RunnerInfo> accuracy("engine_accuracy", {[] { return std::make_unique<AccuracyRunner>(); }});
const Registrar<RunnerInfo> observables("engine_observables", {[] { return std::make_unique<ObservablesRunner>(); }});

}  // namespace
}  // namespace semlb::experiments
