// "division": a cell of a listed type with at least at_elements elements splits through its centroid,
// perpendicular to the long axis of its gyration tensor; the daughter on the +axis side gets the id
// daughter_id(mother, depth) (state.hpp), the same on any number of ranks (the rule: backends/cells.h).
#include "effect.hpp"
#include "cell_fields.hpp"
#include "cell_types.hpp"

namespace semlb::engine {
namespace {

class Division final : public Effect {
 public:
  explicit Division(const Section& s)
      : at_(static_cast<int>(s.integer("at_elements", 20, 2, kMaxSlots - 1))), types_(read_types(s, "types", {"basal"})) {}
  std::string name() const override { return "division"; }
  bool changes_cells() const override { return true; }

  void cell_rules(CellRules& r, const State& s) const override {
    r.division = 1;
    r.depth_field = cell_field_index(s, "division.depth");
    r.division_types = type_mask(types_);
    r.at_elements = at_;
  }

 private:
  int at_;
  std::array<bool, kCellTypes> types_;
};

const CellFieldRegistrar depth("division.depth", {"division", 0.0, "divisions of the cell's lineage so far (an integer: the daughter id's bit)"});
const EffectRegistrar registrar("division", {50, [](const Section& s, const Scene&) { return std::make_unique<Division>(s); }});

}  // namespace
}  // namespace semlb::engine
