// The growth-law registry, and the growth effect that runs the scene's law through the cell stage's rules.
#include "growth_law.hpp"

#include <algorithm>
#include <cmath>

#include "physics/cpu_physics.hpp"
#include "effects/cell_fields.hpp"
#include "effects/chosen_rule.hpp"
#include "effects/effect.hpp"

namespace semlb::engine {
namespace {

// effects.growth: {law: NAME (default clock), offset: um (1), the law's keys}.
class Growth final : public Effect {
 public:
  explicit Growth(const Section& s)
      : law_(ChosenRule::read<GrowthLaw>(s, "law", "clock", SEMLB_CELL_RULE_PARAMS)),
        offset_(s.real("offset", 1.0, 0, 1e6)) {}
  std::string name() const override { return "growth"; }
  bool changes_cells() const override { return true; }
  std::optional<double> growth_phase(double time) const override {
    const auto& cycle = GrowthLaws::at(law_.name).cycle;
    if (!cycle) return std::nullopt;
    const double t = cycle(law_.params);
    return std::fmod(time, t) / t;
  }

  void prepare(State& s) override {  // the law's field at its initial value per cell (e.g. a random phase)
    const GrowthLaw& law = GrowthLaws::at(law_.name);
    if (law.field.empty() || !law.initial) return;
    auto& f = s.cell_fields[law.field];
    if (f.size() == s.cell_id.size()) return;  // restored from a file
    f.resize(s.cell_id.size());
    for (long c = 0; c < s.cells(); ++c)
      f[c] = law.initial(law_.params, uniform01(SEMLB_GROWTH_STREAM, s.cell_id[c], 0, 0));
  }

  void cell_rules(CellRules& r, const State& s) const override {
    r.growth = law_.index;
    const std::string& field = GrowthLaws::at(law_.name).field;
    r.growth_field = field.empty() ? -1 : cell_field_index(s, field);
    std::copy(law_.params.begin(), law_.params.end(), r.growth_p);
    r.offset = offset_;
  }

 private:
  ChosenRule law_;
  double offset_;
};

const Registrar<EffectInfo> effect("growth",
                                   {40, [](const Section& s, const Scene&) { return std::make_unique<Growth>(s); }});

}  // namespace

}  // namespace semlb::engine
