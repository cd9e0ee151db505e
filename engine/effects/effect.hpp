// Effects register by name and run only when a scene lists them: element effects add forces or
// displacements on the backend every step; cell effects change the host state every cell update.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

struct CellContext {
  State& state;
  uint64_t seed;
  double elapsed;  // h since the previous cell update
};

class Effect {
 public:
  virtual ~Effect() = default;
  virtual std::string name() const = 0;
  virtual void prepare(State&) {}                               // allocate this effect's per-cell fields
  virtual bool adds_forces() const { return false; }            // element stage, before integration
  virtual void forces(Backend&, const Grid&) {}
  virtual bool moves_after_integration() const { return false; }  // element stage, after integration
  virtual void after_integration(Backend&, long /*step*/) {}
  virtual bool changes_cells() const { return false; }           // host stage, every cell update
  // Returns true when elements or types changed (the backend then needs a fresh upload).
  virtual bool update_cells(CellContext&) { return false; }
  // The phase in [0, 1) of this effect's growth cycle at `time` (h), if it has one: what the controllers
  // see as Observation::growth_phase (paper Sec. IV-C).
  virtual std::optional<double> growth_phase(double /*time*/) const { return std::nullopt; }
};

struct EffectInfo {
  int order;  // effects run in this order whatever the scene's order
  std::function<std::unique_ptr<Effect>(const Section&, const Scene&)> make;
};
struct EffectRegistrar {
  EffectRegistrar(const std::string& name, EffectInfo info);
};
// The scene's effects, constructed (parameters checked) and sorted by their registered order.
std::vector<std::unique_ptr<Effect>> make_effects(const Scene& scene);
std::vector<std::string> effect_names();

// Helpers shared by the cell effects.
std::array<double, 3> centroid(const State& s, long cell);
// One cell's elements as positions (what division splits).
using Positions = std::vector<std::array<double, 3>>;
Positions elements_of(const State& s, long cell);
// Appends one cell's current elements (3 doubles each) to `out`.
void copy_elements(const State& s, long cell, std::vector<double>& out);
// Rebuilds the element array in one pass after cells gained, lost or swapped elements: emit(c, out)
// appends cell c's elements for c = 0 .. cells()-1 in order, reading the state as it was (positions,
// counts, first elements); each cell's count becomes what it emitted. `added` sizes the new array.
void rewrite_elements(State& s, const std::function<void(long, std::vector<double>&)>& emit, long added);

}  // namespace semlb::engine
