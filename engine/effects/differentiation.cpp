// "differentiation": a basal cell whose centroid rises above basal_height (lost the membrane) becomes
// spinous; a spinous cell becomes granular granular_after hours later. The type selects the adhesion set
// (the rule: backends/cells.h).
#include "cell_fields.hpp"
#include "effect.hpp"

namespace semlb::engine {
namespace {

class Differentiation final : public Effect {
 public:
  explicit Differentiation(const Section& s)
      : basal_height_(s.real("basal_height", 8.0, 0, 1e9)), granular_after_(s.real("granular_after", 40.0, 0, 1e12)) {}
  std::string name() const override { return "differentiation"; }
  bool changes_cells() const override { return true; }

  void cell_rules(CellRules& r, const State& s) const override {
    r.differentiation = 1;
    r.age_field = cell_field_index(s, "differentiation.age");
    r.basal_height = basal_height_;
    r.granular_after = granular_after_;
  }

 private:
  double basal_height_, granular_after_;
};

const CellFieldRegistrar age("differentiation.age", {"differentiation", 0.0, "h since the cell's type last changed"});
const EffectRegistrar registrar("differentiation", {60, [](const Section& s, const Scene&) {
                                                      return std::make_unique<Differentiation>(s);
                                                    }});

}  // namespace
}  // namespace semlb::engine
