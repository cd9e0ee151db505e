// The fate-rule registry, and each rule as a cell effect that decides cell types through CellStage::cell_fate.
#include "fate.hpp"

#include "effects/cell_fields.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// A fate rule listed in the scene: its parameters read once; after each cell stage's growth and division the backend
// applies it to every cell, with the time one stage covers (Scene::cell_stage_h, as the stage's rules).
class FateEffect final : public Effect {
 public:
  FateEffect(const std::string& name, std::vector<double> params, double elapsed_h)
      : call_(fate_call(name, std::move(params))), field_(FateRules::at(name).field), elapsed_h_(elapsed_h) {}
  std::string name() const override { return call_.rule; }
  bool changes_cells() const override { return true; }
  bool after_cell_stage(CellStage& b, State& host) override {
    b.cell_fate(host, call_, field_.empty() ? -1 : cell_field_index(host, field_), elapsed_h_);
    return false;  // types and fields only: no element moved, none was added
  }

 private:
  FateCall call_;
  std::string field_;  // FateRule::field
  double elapsed_h_;
};

}  // namespace

void FateRule::registering(const std::string& name, const FateRule& rule) {
  register_plugin_effect(FateRule::kKind, name, rule, [name](const Section& s, const Scene& scene) {
    return std::make_unique<FateEffect>(name, checked_plugin_params(FateRule::kKind, name, FateRules::at(name).read(s)),
                                        scene.cell_stage_h());
  });
}

FateCall fate_call(const std::string& rule, std::vector<double> params) {
  return {rule, std::move(params), FateRules::at(rule).decides};
}

}  // namespace semlb::engine
