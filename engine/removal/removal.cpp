// The removal-rule registry, and each rule as a cell effect that removes cells through CellStage::remove_cells.
#include "removal.hpp"

#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// A removal rule listed in the scene: its parameters read once; after each cell stage's rules the backend
// removes the cells it flags.
class RemovalEffect final : public Effect {
 public:
  RemovalEffect(const std::string& name, std::vector<double> params) : call_(removal_call(name, std::move(params))) {}
  std::string name() const override { return call_.rule; }
  bool changes_cells() const override { return true; }
  bool after_cell_stage(CellStage& b, State& host) override { return b.remove_cells(host, call_) > 0; }

 private:
  RemovalCall call_;
};

}  // namespace

void RemovalRule::registering(const std::string& name, const RemovalRule& rule) {
  register_plugin_effect(RemovalRule::kKind, name, rule, [name](const Section& s, const Scene&) {
    return std::make_unique<RemovalEffect>(
        name, checked_plugin_params(RemovalRule::kKind, name, RemovalRules::at(name).read(s)));
  });
}

RemovalCall removal_call(const std::string& rule, std::vector<double> params) {
  return {rule, std::move(params), RemovalRules::at(rule).removes};
}

}  // namespace semlb::engine
