// Effects register by name and run only when a scene lists them: element effects add forces or
// displacements on the backend every step; cell effects change the host state every cell update.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "backend.hpp"
#include "scene.hpp"
#include "state.hpp"

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
// Each cell's elements as positions: the form cell effects edit before rebuild().
using CellPositions = std::vector<std::vector<std::array<double, 3>>>;
CellPositions cell_positions(const State& s);
// Rebuilds the element arrays after cells gained, lost or swapped elements: `cells` gives each
// cell's elements as positions; the order of cells is kept.
void rebuild(State& s, const CellPositions& cells);

}  // namespace semlb::engine
