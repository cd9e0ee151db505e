// Effects register by name and run only when a scene lists them: element effects add forces or
// displacements through the backend's force kernels every step; cell effects contribute their parameters to the cell
// stage's rules (physics/cells.h), which the backend runs every cell update, or call its cell stage themselves.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "device/backend.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

class Effect {
 public:
  virtual ~Effect() = default;
  virtual std::string name() const = 0;
  // Sets this effect's per-cell fields on the state before the run, when a value other than the registered initial
  // one is needed (growth: a random phase per cell); every declared field is allocated after (declare_cell_fields).
  virtual void prepare(State&) {}
  virtual bool adds_forces() const { return false; }  // element stage, before integration
  virtual void forces(ForceKernels&, const Grid&) {}  // the part that needs no ghost (local)
  // The part of the forces that needs the ghosts (non-local), run after the ghost exchange arrived.
  virtual void nonlocal_forces(ForceKernels&, const Grid&) {}
  virtual bool moves_after_integration() const { return false; }  // element stage, after integration
  virtual void after_integration(ForceKernels&, long /*step*/) {}
  virtual bool changes_cells() const { return false; }  // cell stage, every cell update
  // Sets this effect's part of the cell stage's rules (growth or division), with the record index
  // of each field it owns in `s` (cell_field_index: s's cell_fields in name order, the record every backend keeps).
  virtual void cell_rules(CellRules&, const State& /*s*/) const {}
  // Cell stage, after the backend ran the rules: changes the backend's cells itself (a removal rule: `host` is the
  // caller's State, stale on OpenCL). True when it removed or added elements (the grid may need refitting).
  virtual bool after_cell_stage(CellStage&, State& /*host*/) { return false; }
  // The phase in [0, 1) of this effect's growth cycle at `time` (h), if it has one: what the controllers
  // see as Observation::growth_phase (paper Sec. IV-C).
  virtual std::optional<double> growth_phase(double /*time*/) const { return std::nullopt; }
};

struct EffectInfo {
  static constexpr const char* kKind = "effect";
  static constexpr const char* kListed = "effects";
  int order;  // effects run in this order whatever the scene's order
  std::function<std::unique_ptr<Effect>(const Section&, const Scene&)> make;
  // A valid section for it (YAML flow map) on the shipped scenes' tissues: what the suites that iterate
  // Effects::names() run it with (tests/engine/effects/test_every_effect.cpp).
  std::string example = "{}";

  // std::logic_error when `name` is one that run.csv's phase columns NAME_s take already (wall, integrate, cells).
  static void registering(const std::string& name, const EffectInfo&);
};
using Effects = PluginKind<EffectInfo>;

// The registration of a plug-in (an element term, pair term, fate or removal rule: a struct with `order` and
// `example`, of kind KIND) under `name` that is also the effect `name` that `make` constructs: `name` names its
// generated code and so must be a C identifier. Called from the kind's `registering`. std::logic_error on a name that
// is not a C identifier or is an effect already.
template <class T>
void register_plugin_effect(const std::string& kind, const std::string& name, const T& entry,
                            std::function<std::unique_ptr<Effect>(const Section&, const Scene&)> make) {
  check_plugin_name(kind, name);
  Effects::add(name, {entry.order, std::move(make), entry.example});
}

// The scene's effects, constructed (parameters checked) and sorted by their registered order.
std::vector<std::unique_ptr<Effect>> make_effects(const Scene& scene);

// The cell stage's rules of the effects that change cells (in their order) for the per-cell fields of `s`: the field
// record holds s.cell_fields.size() doubles per cell, a field no listed effect owns has index -1; rules.single as
// given.
CellRules cell_rules_of(const std::vector<std::unique_ptr<Effect>>& effects, const State& s, bool single);

}  // namespace semlb::engine
