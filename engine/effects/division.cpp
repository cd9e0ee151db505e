// "division": a cell of a listed type with at least at_elements elements splits through its centroid,
// perpendicular to the long axis of its gyration tensor; the daughter on the +axis side gets the id
// daughter_id(mother, depth) (state.hpp), the same on any number of ranks (the rule: backends/cells.h).
#include "effect.hpp"
#include "cell_types.hpp"

namespace semlb::engine {
namespace {

class Division final : public Effect {
 public:
  explicit Division(const Section& s)
      : at_(static_cast<int>(s.integer("at_elements", 20, 2, kMaxSlots - 1))), types_(read_types(s, "types", {"basal"})) {}
  std::string name() const override { return "division"; }
  bool changes_cells() const override { return true; }
  void prepare(State& s) override { s.cell_fields["division.depth"].resize(s.cell_id.size(), 0.0); }

  void cell_rules(CellRules& r) const override {
    r.division = 1;
    r.division_types = type_mask(types_);
    r.at_elements = at_;
  }

 private:
  int at_;
  std::array<bool, kCellTypes> types_;
};

const EffectRegistrar registrar("division", {50, [](const Section& s, const Scene&) { return std::make_unique<Division>(s); }});

}  // namespace
}  // namespace semlb::engine
