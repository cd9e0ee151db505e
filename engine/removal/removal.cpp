// The removal-rule registry, and each rule as a cell effect that removes cells through Backend::remove_cells.
#include "removal.hpp"

#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

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

void RemovalRule::registering(const std::string& name, const RemovalRule& rule) {
  register_plugin_effect(RemovalRule::kKind, name, rule, [name](const Section& s, const Scene&) {
    return std::make_unique<RemovalEffect>(
        name, checked_plugin_params(RemovalRule::kKind, name, RemovalRules::at(name).read(s)));
  });
}

}  // namespace semlb::engine
