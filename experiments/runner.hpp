// Sweep runners registered by name (a manifest's `runner:`): each turns one Job into CSV rows.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "controllers/policy.hpp"
#include "engine/model/scene.hpp"
#include "manifest.hpp"

namespace semlb::experiments {

struct RunOptions {
  bool timing = true;     // false: wall-clock columns are written as 0 (byte-identical reruns)
  std::string trace_dir;  // non-empty: runners that produce traces write them here
  std::string base_dir;   // relative file paths in a manifest are relative to the manifest's folder
  // How MPI runners start their ranks: a program and its arguments, the rank count appended (started without a
  // shell). Empty: this machine's `mpirun --oversubscribe -np` (the slurm launcher's tasks use `srun --mpi=pmix
  // ... --ntasks`).
  std::vector<std::string> mpi_launcher;
  std::string scratch_dir;  // where MPI runs write their files (rank 0 may be on another node); empty: /tmp
  // FILE as a manifest names it: resolve_path(base_dir, FILE).
  std::string resolve(const std::string& file) const;
};

// FILE as the file in folder BASE_DIR names it: absolute as given, else relative to BASE_DIR (the working directory
// when BASE_DIR is empty).
std::string resolve_path(const std::string& base_dir, const std::string& file);

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
  // The MPI ranks the job launches (a launcher reserves them); 0 for runners that run in this process.
  virtual int mpi_ranks(const Job&) const { return 0; }
};

// Scene overrides ("tissue.cells=400") from a job: each of `names` (engine::scene_settings() names, the
// runner's choice) that the job sets, its value type-checked (InputError naming its manifest line), then
// every `scene.KEY` setting as KEY. Shared by the engine runners. FLAGS (when given) gets, per override, where it was
// set ("m.yaml:7: field 'scene.time.dt'", "--set scene.time.dt"): engine::load_scene's names for its errors.
std::vector<std::string> scene_overrides(const Job& job, const std::vector<std::string>& names,
                                         const std::string& manifest, std::vector<std::string>* flags = nullptr);

// The job's scene, for the runners that run the engine: the file its `scene` setting names (relative to
// BASE_DIR, the manifest's folder), with scene_overrides(job, names, manifest) applied. InputError "MANIFEST: field
// 'scene': missing (...)" without a `scene` setting; a mistyped override is scene_overrides' InputError (naming the
// override's line), and so is an error about what an override sets ("m.yaml:13: field 'scene.time.dt': ..."); an
// InputError about the file is prefixed with where `scene` was set ("m.yaml:7: field 'scene': scene.yaml:3: field
// 'tiem': unknown setting"), as is a key of the file's `backend` map the row's backend does not use
// (engine::backend_settings).
engine::Scene job_scene(const Job& job, const std::vector<std::string>& names, const std::string& manifest,
                        const std::string& base_dir);

// "KEY=VALUE;" for every setting, in the job's order: a key for caches and scratch folders (the same settings give
// the same key).
std::string job_key(const Job& job);

// Refuses a setting the runner does not take, before anything runs: the first of the job's settings (in the job's
// order) that is neither in `known` nor accepted by `also` (families such as scene.KEY or POLICY.KEY; may be empty)
// is an InputError naming its manifest line and field: "m.yaml:9: field 'stpes': unknown setting for RUNNER", with
// RUNNER as given ("this runner", "the surrogate runner").
void check_settings(const Job& job, const std::string& manifest, const std::vector<std::string>& known,
                    const std::function<bool(const std::string&)>& also, const std::string& runner);

// True for a scenario.KEY setting: an override of the surrogate's scenario draws (surrogate::make_scenario).
bool is_scenario_key(const std::string& key);
// True for a POLICY.KEY setting (holt.alpha): a key with a '.' that is not a scene.KEY, scenario.KEY or time_model.KEY.
bool is_policy_param(const std::string& key);
// The job's POLICY.KEY settings grouped by policy (surrogate::parse_policy_params); a malformed one is an
// InputError naming its manifest line.
std::map<std::string, PolicyParams> policy_params(const Job& job, const std::string& manifest);
// Builds every policy that has POLICY.KEY settings in the job, also policies this row does not run, so that
// a bad parameter is refused before anything runs; InputError names the parameter's line.
void check_policy_params(const Job& job, const std::string& manifest);

// A registered runner: `const Registrar<RunnerInfo> registrar("name", {factory});` (common/registry.hpp).
struct RunnerInfo {
  static constexpr const char* kKind = "runner";
  static constexpr const char* kListed = "runners";
  std::function<std::unique_ptr<Runner>()> make;
};
using Runners = PluginKind<RunnerInfo>;

std::unique_ptr<Runner> make_runner(const std::string& name, const std::string& manifest);

}  // namespace semlb::experiments
