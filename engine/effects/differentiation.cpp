// "differentiation": a basal cell whose centroid rises above basal_height (lost the membrane) becomes
// spinous; a spinous cell becomes granular granular_after hours later. The type selects the adhesion set.
#include "effect.hpp"

namespace semlb::engine {
namespace {

class Differentiation final : public Effect {
 public:
  explicit Differentiation(const Section& s)
      : basal_height_(s.real("basal_height", 8.0, 0, 1e9)), granular_after_(s.real("granular_after", 40.0, 0, 1e12)) {}
  std::string name() const override { return "differentiation"; }
  bool changes_cells() const override { return true; }
  void prepare(State& s) override { s.cell_fields["differentiation.age"].resize(s.cell_id.size(), 0.0); }

  bool update_cells(CellContext& ctx) override {
    State& s = ctx.state;
    auto& age = s.cell_fields["differentiation.age"];
    bool changed = false;
    for (long c = 0; c < s.cells(); ++c) {
      age[c] += ctx.elapsed;
      int next = s.cell_type[c];
      if (next == kBasal && centroid(s, c)[2] > basal_height_) next = kSpinous;
      else if (next == kSpinous && age[c] >= granular_after_) next = kGranular;
      if (next != s.cell_type[c]) {
        s.cell_type[c] = next;
        age[c] = 0;
        changed = true;
      }
    }
    return changed;
  }

 private:
  double basal_height_, granular_after_;
};

const EffectRegistrar registrar("differentiation", {60, [](const Section& s, const Scene&) {
                                                      return std::make_unique<Differentiation>(s);
                                                    }});

}  // namespace
}  // namespace semlb::engine
