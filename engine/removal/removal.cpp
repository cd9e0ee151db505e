// The removal-rule registry, and each rule as a cell effect that removes cells through Backend::remove_cells.
#include "removal.hpp"

#include "common/registry.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

Registry<RemovalRule>& registry() {
  static Registry<RemovalRule> r;
  return r;
}

// A removal rule listed in the scene: its parameters read once; after each cell stage's rules the backend
// removes the cells it flags.
class RemovalEffect final : public Effect {
 public:
  RemovalEffect(std::string name, std::vector<double> params) : name_(std::move(name)), params_(std::move(params)) {}
  std::string name() const override { return name_; }
  bool changes_cells() const override { return true; }
  bool after_cell_stage(Backend& b, State& host) override { return b.remove_cells(host, name_, params_) > 0; }

 private:
  std::string name_;
  std::vector<double> params_;
};

}  // namespace

RemovalRuleRegistrar::RemovalRuleRegistrar(const std::string& name, RemovalRule rule) {
  register_plugin(registry(), "removal rule", name, std::move(rule), [name](const Section& s, const Scene&) {
    return std::make_unique<RemovalEffect>(name, checked_plugin_params("removal rule", name, removal_rule(name).read(s)));
  });
}

const RemovalRule& removal_rule(const std::string& name) { return registry().at("removal rule", name); }

std::vector<std::string> removal_rule_names() { return registry().names(); }

}  // namespace semlb::engine
