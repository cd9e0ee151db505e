// The fate-rule registry, and each rule as a cell effect that decides cell types through Backend::cell_fate.
#include "fate.hpp"

#include "effects/cell_fields.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// A fate rule listed in the scene: its parameters read once; after each cell stage's growth and division the backend
// applies it to every cell, with the time one stage covers (Scene::cell_stage_h, as the stage's rules).
class FateEffect final : public Effect {
 public:
  FateEffect(std::string name, std::vector<double> params, double elapsed_h)
      : name_(std::move(name)), params_(std::move(params)), elapsed_h_(elapsed_h) {}
  std::string name() const override { return name_; }
  bool changes_cells() const override { return true; }
  bool after_cell_stage(Backend& b, State& host) override {
    const std::string& field = FateRules::at(name_).field;
    b.cell_fate(host, name_, params_, field.empty() ? -1 : cell_field_index(host, field), elapsed_h_);
    return false;  // types and fields only: no element moved, none was added
  }

 private:
  std::string name_;
  std::vector<double> params_;
  double elapsed_h_;
};

}  // namespace

void FateRule::registering(const std::string& name, const FateRule& rule) {
  register_plugin_effect(FateRule::kKind, name, rule, [name](const Section& s, const Scene& scene) {
    return std::make_unique<FateEffect>(name, checked_plugin_params(FateRule::kKind, name, FateRules::at(name).read(s)),
                                        scene.cell_stage_h());
  });
}

}  // namespace semlb::engine
