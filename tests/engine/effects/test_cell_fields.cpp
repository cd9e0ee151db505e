// Per-cell fields as effects declare them (effects/cell_fields.hpp): the registry's rules, what a run declares, and a
// field that no core file names carried by every backend through the cell stage (daughters inherit it), the removal
// of cells, the migration's take_leavers / append_cells and the state files, without changing the shipped fields.
#include <gtest/gtest.h>

#include <algorithm>

#include "engine/physics/cpu_physics.hpp"
#include "engine/model/slices.hpp"
#include "engine/effects/cell_fields.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "../engine_fixtures.hpp"

namespace semlb::engine {
namespace {

// A field of an effect that is not shipped, registered by this test binary only (its cells are tagged by hand).
// "clonal.mark" sorts before every shipped field, so every rule's index in the record moves by one.
const Registrar<CellFieldInfo> clonal("clonal.mark", {"clonal", -1.0, "the lineage's root id / 4 (test only)"});

// What clonal.mark holds for a cell of `id`: its lineage's root id / 4, which its daughters inherit.
double mark_of(uint64_t id) { return static_cast<double>(id & ((uint64_t{1} << kRootIdBits) - 1)) / 4; }

void expect_marked(const State& s, const std::string& where) {
  const auto& mark = s.cell_fields.at("clonal.mark");
  ASSERT_EQ(mark.size(), s.cell_id.size()) << where;
  for (long c = 0; c < s.cells(); ++c) EXPECT_EQ(mark[c], mark_of(s.cell_id[c])) << where << ", cell " << s.cell_id[c];
}

TEST(CellFields, TheRegistryHoldsTheShippedFieldsAndRefusesBadNames) {
  const auto names = CellFields::names();
  for (const char* n : {"differentiation.age", "division.depth", "growth.clock"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  EXPECT_EQ(CellFields::find("division.depth")->effect, "division");
  EXPECT_EQ(CellFields::find("no.such"), nullptr);
  EXPECT_NE(CellFields::known().find("division.depth, growth.clock"), std::string::npos) << CellFields::known();
  EXPECT_THROW(Registrar<CellFieldInfo>("clock", {"growth", 0.0, ""}), std::logic_error);    // no "EFFECT." prefix
  EXPECT_THROW(Registrar<CellFieldInfo>("growth.", {"growth", 0.0, ""}), std::logic_error);  // no name after it
  EXPECT_THROW(Registrar<CellFieldInfo>("division.clock", {"growth", 0.0, ""}),
               std::logic_error);  // another effect's prefix
  EXPECT_THROW(Registrar<CellFieldInfo>("growth.clock", {"growth", 0.0, ""}), std::logic_error);  // registered twice
}

TEST(CellFields, ARunDeclaresTheFieldsOfItsListedEffectsAndKeepsRestoredOnes) {
  State s = testing::random_state(4, 2, 5.0, 1);
  s.cell_fields["division.depth"] = {1, 2, 3, 4};  // as restored from a file: kept
  declare_cell_fields(s, {"mechanics", "division", "clonal"});
  EXPECT_EQ(s.cell_fields.size(), 2u);
  EXPECT_EQ(s.cell_fields.at("division.depth"), (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(s.cell_fields.at("clonal.mark"), std::vector<double>(4, -1.0));  // the registered initial value
  EXPECT_EQ(cell_field_index(s, "clonal.mark"), 0);
  EXPECT_EQ(cell_field_index(s, "division.depth"), 1);
  EXPECT_EQ(cell_field_index(s, "growth.clock"), -1);
  s.cell_fields["growth.clock"] = {0.5};  // not one value per cell
  EXPECT_THROW(declare_cell_fields(s, {}), std::logic_error);
}

// The epidermis with every cell effect and desquamation on a small, fast sheet (cells grow, divide, differentiate
// and are shed within 300 steps), its cells tagged with clonal.mark, on every backend and precision: the same state
// as without the tag, the tag inherited by every daughter, kept through a migration round trip and a state file.
TEST(CellFields, AFieldNoCoreFileNamesIsCarriedByEveryBackend) {
  const auto dir = test::fresh_dir("cell_fields");
  for (const auto& [backend, precision] : testing::backend_precisions()) {
    const std::string where = backend + " " + precision;
    auto scene = load_scene(
        test::source("scenes/epidermis.yaml"),
        {"tissue.cells=12", "backend.name=" + backend, "backend.precision=" + precision, "effects.growth.cycle_time=1",
         "effects.differentiation.basal_height=2", "effects.differentiation.granular_after=1",
         "effects.noise.diffusion=0", "effects.desquamation={height: 6}"});
    const State tissue = make_tissue(scene);
    State tagged = tissue;
    for (uint64_t id : tagged.cell_id) tagged.cell_fields["clonal.mark"].push_back(mark_of(id));
    Simulation plain(scene, tissue), sim(scene, tagged);
    plain.advance(300);
    sim.advance(300);
    State out = sim.sync();
    State want = plain.sync();
    EXPECT_EQ(out.hash(), want.hash()) << where;
    EXPECT_LT(out.cells(),
              12 + std::count_if(out.cell_id.begin(), out.cell_id.end(), [](uint64_t id) { return id >> kRootIdBits; }))
        << where << ": cells were shed";
    ASSERT_TRUE(std::any_of(out.cell_id.begin(), out.cell_id.end(), [](uint64_t id) { return id >> kRootIdBits; }))
        << where << ": cells divided";
    for (const auto& [name, f] : want.cell_fields) EXPECT_EQ(out.cell_fields.at(name), f) << where << ": " << name;
    expect_marked(out, where);

    // The migration: the cells right of the middle leave rank 0 of two and come back (after the stayers).
    double lo = 1e30, hi = -1e30;
    for (long c = 0; c < out.cells(); ++c) {
      const double x = centroid(out, c)[0];
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
    const SliceMap map{2, lo, (hi - lo) / 2 + 1e-6};
    State host = out, leavers;
    std::vector<int> owner;
    sim.backend().take_leavers(host, map, {1}, 0, leavers, owner);
    ASSERT_GT(leavers.cells(), 0) << where;
    ASSERT_LT(leavers.cells(), out.cells()) << where;
    expect_marked(leavers, where + ", leavers");
    sim.backend().append_cells(host, leavers);
    sim.backend().download(host);
    const State back = host.canonical();
    EXPECT_EQ(back.cell_id, out.canonical().cell_id) << where;
    expect_marked(back, where + ", after the round trip");

    write_state(dir + "/state.h5", out, {});
    const State read = read_state(dir + "/state.h5");
    EXPECT_EQ(read.cell_fields, out.cell_fields) << where;
  }
}

}  // namespace
}  // namespace semlb::engine
