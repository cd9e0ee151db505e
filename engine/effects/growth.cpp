// "growth": cells of the listed types add one element every cycle_time / (max_elements - min_elements)
// hours (10 -> 20 elements per cycle by default), placed near the centroid (the rule: backends/cells.h);
// with `front: {x0, speed}` only cells behind a proliferative front at x0 + speed * t (um) grow.
#include <cmath>

#include "backends/cpu_physics.hpp"
#include "effect.hpp"
#include "cell_fields.hpp"
#include "cell_types.hpp"

namespace semlb::engine {
namespace {

class Growth final : public Effect {
 public:
  explicit Growth(const Section& s)
      : cycle_(s.real("cycle_time", 20.0, 1e-9, 1e12)),
        min_(static_cast<int>(s.integer("min_elements", 10, 1, kMaxSlots - 1))),
        max_(static_cast<int>(s.integer("max_elements", 20, 1, kMaxSlots - 1))),
        offset_(s.real("offset", 1.0, 0, 1e6)),
        types_(read_types(s, "types", {"basal"})) {
    if (max_ <= min_) s.fail("max_elements", "must exceed min_elements");
    if (s.has("front")) {  // the proliferative wave: both keys required, nothing else
      const Section f = s.child("front");
      for (const char* k : {"x0", "speed"})
        if (!f.has(k)) f.fail(k, "missing (front: {x0: um, speed: um/h})");
      front_ = true;
      front_x0_ = f.real("x0", 0.0, -1e12, 1e12);
      front_speed_ = f.real("speed", 0.0, -1e12, 1e12);
      f.finish();
    }
  }
  std::string name() const override { return "growth"; }
  bool changes_cells() const override { return true; }
  std::optional<double> growth_phase(double time) const override { return std::fmod(time, cycle_) / cycle_; }

  void prepare(State& s) override {  // a random phase of the element-addition clock per cell
    auto& clock = s.cell_fields["growth.clock"];
    if (clock.size() == s.cell_id.size()) return;  // restored from a file
    clock.resize(s.cell_id.size());
    for (long c = 0; c < s.cells(); ++c) clock[c] = period() * uniform01(SEMLB_GROWTH_STREAM, s.cell_id[c], 0, 0);
  }

  void cell_rules(CellRules& r, const State& s) const override {
    r.growth = 1;
    r.clock_field = cell_field_index(s, "growth.clock");
    r.growth_types = type_mask(types_);
    r.max_elements = max_;
    r.period = period();
    r.offset = offset_;
    r.front = front_ ? 1 : 0;
    r.front_x0 = front_x0_;
    r.front_speed = front_speed_;
  }

 private:
  double period() const { return cycle_ / (max_ - min_); }

  double cycle_;
  int min_, max_;
  double offset_;
  bool front_ = false;
  double front_x0_ = 0, front_speed_ = 0;  // um, um/h
  std::array<bool, kCellTypes> types_;
};

const CellFieldRegistrar clock("growth.clock", {"growth", 0.0, "h since the cell last added an element (starts at a random phase)"});
const EffectRegistrar registrar("growth", {40, [](const Section& s, const Scene&) { return std::make_unique<Growth>(s); }});

}  // namespace
}  // namespace semlb::engine
