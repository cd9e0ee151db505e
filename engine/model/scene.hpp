// Scene files (YAML): domain, tissue, time stepping, output cadence, backend and the listed effects.
// Format and defaults: docs/engine.md "Scene format". Errors name the file, line and field.
#pragma once
#include <yaml-cpp/yaml.h>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/settings.hpp"

namespace semlb::engine {

// The dotted keys an override gave, and the maps it made on the way to one, each with its Origin: the flag and the
// field it set.
using Overridden = std::map<std::string, Origin>;

// Typed, checked access to one YAML map of a scene: a semlb::Settings (common/settings.hpp: strict typed reads
// real / integer / text / boolean / texts with ranges, "FILE:LINE: field 'a.b': " errors, finish() refusing keys
// nobody read) over the map's keys, plus its child maps. A key set by --set, or inside a map --set gave, is
// blamed on that flag ("--set a.b: ", "--set a: field 'a.b': ").
class Section : public Settings {
 public:
  // `node`: a YAML map (or null: empty); `path`: its dotted path ("" at the top); `file`: the scene file;
  // `overridden`: the dotted keys --set gave (may be null).
  Section(YAML::Node node, std::string path, std::string file, std::shared_ptr<const Overridden> overridden);
  // KEY's map as a Section (marks KEY read); an empty section when absent; "must be a map of settings" otherwise.
  Section child(const std::string& key) const;
  const std::string& file() const { return file_; }

 private:
  YAML::Node node_;
  std::string file_;
  std::shared_ptr<const Overridden> overridden_;
};

// The backend a scene runs on: `backend.name` and `backend.precision`, read with the scene; every other key of the
// `backend` map is the chosen backend's own, read by that backend when it is made (backends/backend.hpp
// backend_settings: a key it does not use is an error naming it).
struct BackendConfig {
  std::string name = "cpu-binned";
  std::string precision = "double";  // double | float
  int threads = 0;                   // cpu-binned's `threads`: 0 = all hardware threads
  std::string platform;  // the OpenCL backends' `platform`: a platform name substring; empty: see docs/engine.md
  int device = 0;        // the OpenCL backends' `device`: the index within the chosen platform
  int local_rank = 0;    // added to `device` (one device per local MPI rank)
  double skin = 0.0;     // um, opencl-binned's `skin`: its neighbour list (docs/engine.md); 0: none, bins every step
  bool newton = false;   // opencl-binned's `newton`: a half list, each pair once (docs/engine.md); needs skin > 0
  // opencl-binned's `list_bin_divisions`: the list's bins of edge (cutoff + skin) / N, its build over the (2N + 1)^3
  // bins around a slot (docs/engine.md "Neighbour list"); 1..3, needs skin > 0
  int list_bin_divisions = 1;
  // The OpenCL backends' `pair_exp`, the pair force law's exp (docs/engine.md "Pair exp"): builtin | ranged (double) |
  // native; read as the precision's default, native in float and ranged in double, when the scene leaves it out.
  std::string pair_exp;
  // The scene's `backend` map (null: a config made in code, its fields as set), whose keys beside name and precision
  // the backend reads (backend_settings).
  std::shared_ptr<const Section> settings;
  // Not a scene key: the pair term the scene lists (pairs/pair_term.hpp scene_pair_term, set by Simulation), which
  // the OpenCL backends build their program for; another term asked for later rebuilds it.
  std::string pair_term = "mechanics";
  // Not a scene key: the OpenCL backends time the step's kernels on the device (Backend::step_device_seconds); set by
  // Simulation when its decomposed run has decomposition.timing: device.
  bool device_timing = false;
};

struct Scene {
  std::string path, name, text;  // text: the scene after overrides, copied next to results
  uint64_t seed = 1;
  std::array<double, 3> box_lo{}, box_hi{};  // resolved by the tissue generator when "auto"
  bool auto_box = true;
  double cutoff = 8.75;  // um
  double dt = 0.01;      // h
  long steps = 1000;
  double friction = 1.0;          // eta
  double max_displacement = 1.0;  // um per step; larger stops the run
  long cell_update_every = 10;
  // h one cell stage covers (dt x cell_update_every): the elapsed time every cell rule advances by.
  double cell_stage_h() const { return dt * static_cast<double>(cell_update_every); }
  long snapshot_every = 0, log_every = 100, checkpoint_every = 0;  // 0 = never (log: every 100)
  bool record_workload = false;  // output.workload: DIR/workload.h5, the per-event workload (controllers/workload.hpp)
  bool write_final = true;       // output.final: DIR/final.h5 and final.xmf at the end (false: the state stays put)
  BackendConfig backend;
  std::shared_ptr<Section> tissue;
  std::shared_ptr<Section> decomposition;                // read by Decomposition::from_scene (decomposed runs only)
  std::vector<std::pair<std::string, Section>> effects;  // in file order
};

// A scene setting that CLI flags and sweep manifests give by name (`cells` sets tissue.cells), with the type
// of its value; any other scene key is set with `--set KEY=VALUE` (a manifest's `scene.KEY`).
struct SceneSetting {
  enum class Type { text, integer, real };
  const char* name;  // the flag / manifest name
  const char* key;   // the scene key it sets
  Type type;
};
// The named settings, each written once here; docs/engine.md "Scene format" gives their ranges and defaults.
const std::vector<SceneSetting>& scene_settings();
// The named setting `name` (scene_settings()); std::logic_error for a name that is not one (a programming error).
const SceneSetting& scene_setting(const std::string& name);
// The override "KEY=VALUE" of the named setting. The value is checked against the setting's type (parsed
// strictly, common/text_io.hpp; InputError prefixed by `where`), its range when the scene is loaded.
// std::logic_error for a name that is not in scene_settings() (a programming error).
std::string scene_override(const std::string& name, const std::string& value, const std::string& where);

// Loads FILE and applies `key.path=value` overrides (the value is YAML), in order. Throws InputError. An error about
// an override's key, or a key inside a map it gave or made, names flags[i] when given and not empty (the command-line
// flag it came from, e.g. "--backend"), else "--set key.path". An override named by a flag that would hide what an
// earlier unnamed one (a --set) gave is refused: "--backend: backend.name is also given by --set backend; give it
// once" (the --set's key, a map of it holding the flag's key, or a value that is not a map on its way).
Scene load_scene(const std::string& file, const std::vector<std::string>& overrides,
                 const std::vector<std::string>& flags = {});
// Same from text (FILE only names the source in messages).
Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides,
                  const std::vector<std::string>& flags = {});

}  // namespace semlb::engine
