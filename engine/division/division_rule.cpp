// The division-rule registry, and the division effect that runs the scene's rule through the cell stage's rules.
#include "division_rule.hpp"

#include <algorithm>

#include "physics/cpu_physics.hpp"
#include "effects/cell_fields.hpp"
#include "effects/cell_types.hpp"
#include "effects/chosen_rule.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// effects.division: {rule: NAME (default long_axis), the rule's keys}.
class Division final : public Effect {
 public:
  explicit Division(const Section& s)
      : rule_(ChosenRule::read<DivisionRule>(s, "rule", "long_axis", SEMLB_CELL_RULE_PARAMS)) {}
  std::string name() const override { return "division"; }
  bool changes_cells() const override { return true; }

  void cell_rules(CellRules& r, const State& s) const override {
    r.division = rule_.index;
    r.depth_field = cell_field_index(s, "division.depth");
    std::copy(rule_.params.begin(), rule_.params.end(), r.division_p);
  }

 private:
  ChosenRule rule_;
};

const Registrar<CellFieldInfo> depth("division.depth",
                                     {"division", 0.0,
                                      "divisions of the cell's lineage so far (an integer: the daughter id's bit)"});
const Registrar<EffectInfo> effect("division",
                                   {50, [](const Section& s, const Scene&) { return std::make_unique<Division>(s); }});

}  // namespace

std::vector<double> read_size_trigger(const Section& s) {
  const long at = s.integer("at_elements", 20, 2, kMaxSlots - 1);
  return {static_cast<double>(type_mask(read_types(s, "types", {"basal"}))), static_cast<double>(at)};
}

}  // namespace semlb::engine
