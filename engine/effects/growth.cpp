// "growth": cells of the listed types add one element every cycle_time / (max_elements - min_elements)
// hours (10 -> 20 elements per cycle by default), placed near the centroid.
#include <cmath>

#include "backends/cpu_physics.hpp"
#include "effect.hpp"
#include "cell_types.hpp"

namespace semlb::engine {
namespace {

constexpr uint64_t kGrowthStream = 0x67726f77ULL;

class Growth final : public Effect {
 public:
  explicit Growth(const Section& s)
      : cycle_(s.real("cycle_time", 20.0, 1e-9, 1e12)),
        min_(static_cast<int>(s.integer("min_elements", 10, 1, kMaxSlots - 1))),
        max_(static_cast<int>(s.integer("max_elements", 20, 1, kMaxSlots - 1))),
        offset_(s.real("offset", 1.0, 0, 1e6)),
        types_(read_types(s, "types", {"basal"})) {
    if (max_ <= min_) s.fail("max_elements", "must exceed min_elements");
  }
  std::string name() const override { return "growth"; }
  bool changes_cells() const override { return true; }
  std::optional<double> growth_phase(double time) const override { return std::fmod(time, cycle_) / cycle_; }

  void prepare(State& s) override {  // a random phase of the element-addition clock per cell
    auto& clock = s.cell_fields["growth.clock"];
    if (clock.size() == s.cell_id.size()) return;  // restored from a file
    clock.resize(s.cell_id.size());
    for (long c = 0; c < s.cells(); ++c) clock[c] = period() * uniform01(kGrowthStream, s.cell_id[c], 0, 0);
  }

  bool update_cells(CellContext& ctx) override {
    State& s = ctx.state;
    auto& clock = s.cell_fields["growth.clock"];
    std::vector<int> births(s.cells(), 0);  // elements each cell adds now
    bool any = false;
    for (long c = 0; c < s.cells(); ++c) {
      if (!types_[s.cell_type[c]]) continue;
      clock[c] += ctx.elapsed;
      for (; clock[c] >= period(); clock[c] -= period())
        if (s.cell_count[c] + births[c] < max_) ++births[c];  // a full cell waits for division
      any = any || births[c] > 0;
    }
    if (!any) return false;
    long added = 0;
    for (int b : births) added += b;
    rewrite_elements(s, [&](long c, std::vector<double>& out) {
      copy_elements(s, c, out);
      for (int b = 0; b < births[c]; ++b) {
        const auto p = newborn(s, c, ctx.seed, s.cell_count[c] + b);
        out.insert(out.end(), p.begin(), p.end());
      }
    }, added);
    return true;
  }

 private:
  double period() const { return cycle_ / (max_ - min_); }

  // Centroid + offset * a random unit vector keyed by (seed, cell, step, slot).
  std::array<double, 3> newborn(const State& s, long c, uint64_t seed, int slot) const {
    const auto ctr = centroid(s, c);
    const uint64_t key = element_key(s.cell_id[c], slot);
    double u[3], norm = 0;
    for (int d = 0; d < 3; ++d) {
      u[d] = gaussian(seed ^ kGrowthStream, key, static_cast<uint64_t>(s.step), d);
      norm += u[d] * u[d];
    }
    norm = std::sqrt(norm) + 1e-300;
    return {ctr[0] + offset_ * u[0] / norm, ctr[1] + offset_ * u[1] / norm, ctr[2] + offset_ * u[2] / norm};
  }

  double cycle_;
  int min_, max_;
  double offset_;
  std::array<bool, kCellTypes> types_;
};

const EffectRegistrar registrar("growth", {40, [](const Section& s, const Scene&) { return std::make_unique<Growth>(s); }});

}  // namespace
}  // namespace semlb::engine
