// Every registered fate rule on every backend this machine runs, in both precisions: the backend gives every cell the
// type and field its evaluator decides (on the backend's own positions), its elements that type, and moves nothing;
// a scene lists it as an effect. Then differentiation's sequence by hand and its scene errors.
#include <gtest/gtest.h>

#include <algorithm>

#include "engine/backends/backend.hpp"
#include "engine/physics/cpu_physics.hpp"
#include "engine/effects/cell_fields.hpp"
#include "engine/effects/effect.hpp"
#include "engine/fates/fate.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

// `s` after rule `name` with `params`, field index `field`, `elapsed` h: the reference.
State decided_by(const std::string& name, State s, const std::vector<double>& params, int field, double elapsed) {
  std::vector<double>* column = s.cell_field_at(field);
  for (long c = 0; c < s.cells(); ++c) {
    const auto ctr = centroid(s, c);
    double f = column ? (*column)[c] : 0.0;
    FateRules::at(name).decides(ctr[0], ctr[1], ctr[2], s.cell_count[c], elapsed, params.data(), &s.cell_type[c], &f);
    if (column) (*column)[c] = f;
  }
  return s;
}

TEST(FateRules, EveryRuleOnEveryBackendDecidesWhatItsEvaluatorDecides) {
  ASSERT_FALSE(FateRules::names().empty());
  State s = testing::random_state(60, 8, 24.0, 31);
  s.cell_fields["growth.clock"] = std::vector<double>(s.cells());
  s.cell_fields["division.depth"] = std::vector<double>(s.cells());
  for (long c = 0; c < s.cells(); ++c)
    s.cell_fields["growth.clock"][c] = 0.25 * c, s.cell_fields["division.depth"][c] = c % 5;
  for (const auto& name : FateRules::names()) {
    const auto names = Effects::names();
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name << " is not an effect";
    const FateRule& rule = FateRules::at(name);
    State start = s;
    if (!rule.field.empty()) {
      start.cell_fields[rule.field] = std::vector<double>(s.cells());
      for (long c = 0; c < s.cells(); ++c) start.cell_fields[rule.field][c] = 7.0 * (c % 9);  // ages around thresholds
    }
    const int field = rule.field.empty() ? -1 : cell_field_index(start, rule.field);
    const auto params = testing::section_params(name, rule.example, rule.read);
    for (const auto& [backend, precision] : testing::backend_precisions()) {
      auto b = testing::backend(backend, precision);
      b->upload(start);
      State before = start;
      b->download(before);  // the positions as this backend holds them (float: rounded)
      State host = before;
      for (int stage = 1; stage <= 3; ++stage) {
        const State want = decided_by(name, host, params, field, 10.0);
        b->cell_fate(host, fate_call(name, params), field, 10.0);
        b->download(host);
        EXPECT_EQ(host.cell_type, want.cell_type)
            << name << " on " << backend << " " << precision << ", stage " << stage;
        EXPECT_EQ(host.cell_fields, want.cell_fields) << name << " on " << backend << " " << precision;
        EXPECT_EQ(host.position, before.position) << name << " moved elements on " << backend;
      }
      EXPECT_NE(host.cell_type, before.cell_type) << name << ": the example changes no cell";
      // The elements carry their cell's new type: type-dependent pair forces equal those of a backend given the
      // decided state afresh (on OpenCL the kernel rewrote each element's info on the device).
      const PairForces typed = testing::pair_forces("mechanics", testing::kTypedMorse, 8.75);
      const Grid grid = Grid::cover({0, 0, 0}, {24, 24, 24}, 8.75);
      auto fresh = testing::backend(backend, precision);
      fresh->upload(host);
      for (Backend* x : {b.get(), fresh.get()}) {
        x->zero_forces();
        x->pair_forces(typed, grid);
      }
      EXPECT_EQ(b->fixed_forces(), fresh->fixed_forces()) << name << ": the elements' types on " << backend;
      if (backend.rfind("opencl", 0) == 0) {
        EXPECT_EQ(b->launches().at("fate_" + name), 3);
      }
    }
  }
}

TEST(FateRules, DifferentiationSettingsAreChecked) {
  testing::expect_errors_name_fields(
      {{"effects.differentiation={basal_height: -1}", "effects.differentiation.basal_height"},
       {"effects.differentiation={granular_after: x}", "effects.differentiation.granular_after"},
       {"effects.differentiation={basal: 3}", "effects.differentiation.basal"}});
}

// A call made by hand for a rule that is not registered is refused on every backend (no evaluator on the C++ ones, no
// kernel fate_NAME on OpenCL), as is the name by the call maker.
TEST(FateRules, ACallForAnUnregisteredRuleIsALogicErrorOnEveryBackend) {
  EXPECT_THROW(fate_call("no_such_rule", {}), std::logic_error);
  testing::expect_logic_error_on_every_backend(testing::random_state(6, 4, 12.0, 5), [](Backend& b, State& host) {
    b.cell_fate(host, FateCall{"no_such_rule", {}}, -1, 1.0);
  });
}

}  // namespace
}  // namespace semlb::engine
