// Every registered removal rule on every backend this machine runs, in both precisions: the backend removes exactly
// the cells its evaluator flags (on the backend's own positions), keeps the others in order with their fields, and
// a scene lists it as an effect.
#include <gtest/gtest.h>

#include <algorithm>

#include "engine/backends/backend.hpp"
#include "engine/physics/cpu_physics.hpp"
#include "engine/effects/effect.hpp"
#include "engine/removal/removal.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

// `s` without the cells that rule `name` flags: the reference.
State kept_by(const std::string& name, const State& s, const std::vector<double>& params) {
  State out = empty_like(s);
  for (long c = 0; c < s.cells(); ++c) {
    const auto ctr = centroid(s, c);
    if (!RemovalRules::at(name).removes(ctr[0], ctr[1], ctr[2], s.cell_type[c], s.cell_count[c], params.data()))
      copy_cell(s, c, out);
  }
  out.reindex();
  return out;
}

TEST(RemovalRules, EveryRuleOnEveryBackendRemovesWhatItsEvaluatorFlags) {
  if (RemovalRules::names().empty()) GTEST_SKIP() << "no removal rule registered";
  State s = testing::random_state(60, 8, 24.0, 31);
  s.cell_fields["growth.clock"] = std::vector<double>(s.cells());
  s.cell_fields["division.depth"] = std::vector<double>(s.cells());
  for (long c = 0; c < s.cells(); ++c)
    s.cell_fields["growth.clock"][c] = 0.25 * c, s.cell_fields["division.depth"][c] = c % 5;
  for (const auto& name : RemovalRules::names()) {
    const auto names = Effects::names();
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name << " is not an effect";
    const auto params = testing::section_params(name, RemovalRules::at(name).example, RemovalRules::at(name).read);
    for (const auto& [backend, precision] : testing::backend_precisions()) {
      auto b = testing::backend(backend, precision);
      b->upload(s);
      State before = s;
      b->download(before);  // the positions as this backend holds them (float: rounded)
      const State want = kept_by(name, before, params);
      ASSERT_GT(want.cells(), 0) << name << ": the example removes every cell";
      ASSERT_LT(want.cells(), s.cells()) << name << ": the example removes nothing";
      State host = before;
      EXPECT_EQ(b->remove_cells(host, removal_call(name, params)), s.cells() - want.cells())
          << name << " on " << backend;
      b->download(host);
      EXPECT_EQ(b->counts(host), (std::pair<long, long>{want.cells(), want.elements()})) << name << " on " << backend;
      EXPECT_EQ(host.cell_id, want.cell_id) << name << " on " << backend << " " << precision;
      EXPECT_EQ(host.position, want.position) << name << " on " << backend << " " << precision;
      EXPECT_EQ(host.cell_fields, want.cell_fields) << name << " on " << backend << " " << precision;
      if (backend.rfind("opencl", 0) == 0) {
        EXPECT_EQ(b->launches().at("remove_" + name), 1);
      }
      // A second pass finds nothing more to remove and changes nothing.
      EXPECT_EQ(b->remove_cells(host, removal_call(name, params)), 0);
    }
  }
}

// A call made by hand for a rule that is not registered is refused on every backend (no evaluator on the C++ ones, no
// kernel remove_NAME on OpenCL), as is the name by the call maker.
TEST(RemovalRules, ACallForAnUnregisteredRuleIsALogicErrorOnEveryBackend) {
  EXPECT_THROW(removal_call("no_such_rule", {}), std::logic_error);
  testing::expect_logic_error_on_every_backend(testing::random_state(6, 4, 12.0, 5), [](Backend& b, State& host) {
    b.remove_cells(host, RemovalCall{"no_such_rule", {}});
  });
}

}  // namespace
}  // namespace semlb::engine
