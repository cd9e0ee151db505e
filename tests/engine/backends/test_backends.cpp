// Compare tests of the element kernels: every backend against the serial all-pairs reference on random
// inputs, order and thread independence, and the exact kernels a run launches (none of unlisted effects).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>

#include "engine/physics/cpu_physics.hpp"
#include "engine/effects/cell_types.hpp"
#include "engine/effects/effect.hpp"
#include "engine/simulation/simulation.hpp"
#include "../engine_fixtures.hpp"
#include "../../run_command.hpp"

namespace semlb::engine {
namespace {

using testing::available_backends;
using testing::random_state;
using testing::scene_from;

// Positions after `steps` steps of mechanics + membrane on a random tissue, with the given backend.
// `skin`: opencl-binned's neighbour list (0: the stencil over fresh bins every step).
State run(const std::string& backend, const std::string& precision, State s, long steps, int threads = 0,
          double side = 40, const std::string& skin = "1") {
  auto scene = scene_from(testing::kMechanicsYaml, {"backend.name=" + backend, "backend.precision=" + precision,
                                                    "backend.cpu-binned.threads=" + std::to_string(threads),
                                                    "effects.membrane={}", "backend.opencl-binned.skin=" + skin});
  scene.box_lo = {0, 0, 0};
  scene.box_hi = {side, side, side};
  Simulation sim(scene, std::move(s));
  sim.advance(steps);
  return sim.sync();
}

double max_difference(const State& a, const State& b) {
  double d = 0;
  for (size_t i = 0; i < a.position.size(); ++i) d = std::max(d, std::abs(a.position[i] - b.position[i]));
  return d;
}

TEST(Backends, BinnedEqualsAllPairsBitForBit) {
  for (const char* precision : {"double", "float"}) {
    const auto s = random_state(60, 9, 40.0, 11);
    EXPECT_EQ(run("serial", precision, s, 5).hash(), run("cpu-binned", precision, s, 5).hash()) << precision;
  }
}

TEST(Backends, OpenClMatchesTheCppReference) {
  const auto backends = available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end())
    GTEST_SKIP() << "no OpenCL platform";
  const auto s = random_state(60, 9, 40.0, 12);
  const State ref = run("serial", "double", s, 5);
  // Stated tolerances (um after 5 steps): double 1e-9 (exp/sqrt ulps of the device library), float 1e-3.
  EXPECT_LT(max_difference(ref, run("opencl-allpairs", "double", s, 5)), 1e-9);
  EXPECT_LT(max_difference(ref, run("opencl-binned", "double", s, 5)), 1e-9);
  EXPECT_LT(max_difference(ref, run("opencl-binned", "float", s, 5)), 1e-3);
  // The two device variants share the fixed-point sums, so they agree bit for bit with each other.
  EXPECT_EQ(run("opencl-allpairs", "double", s, 5).hash(), run("opencl-binned", "double", s, 5).hash());
  EXPECT_EQ(run("opencl-allpairs", "float", s, 5).hash(), run("opencl-binned", "float", s, 5, 0, 40, "0").hash());
  // A grid of 22^3 = 10,648 bins: the bin scan spans 42 work-groups.
  const auto wide = random_state(3000, 4, 200.0, 15);
  EXPECT_EQ(run("opencl-allpairs", "float", wide, 2, 0, 200).hash(),
            run("opencl-binned", "float", wide, 2, 0, 200).hash());
  EXPECT_EQ(run("serial", "float", wide, 2, 0, 200).hash(), run("cpu-binned", "float", wide, 2, 0, 200).hash());
}

// The pair force law's exp (backend.pair_exp, physics/exp.h): each variant within its stated error of the built-in exp
// after 5 steps (double's ranged as close as the device's exp to the C++ backends' libm; native, float's exp, within
// float's tolerance), and both OpenCL backends alike bit for bit. That each value reaches the kernels as the exp it
// names: tests/engine/physics/test_exp.cpp.
TEST(Backends, PairExpVariantsStayWithinTheirErrorOfTheBuiltin) {
  const auto backends = available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end())
    GTEST_SKIP() << "no OpenCL platform";
  const auto s = random_state(60, 9, 40.0, 12);
  const auto with = [&](const std::string& backend, const std::string& precision, const std::string& exp) {
    auto scene = scene_from(testing::kMechanicsYaml, {"backend.name=" + backend, "backend.precision=" + precision,
                                                      "effects.membrane={}", "backend.pair_exp=" + exp});
    scene.box_lo = {0, 0, 0};
    scene.box_hi = {40, 40, 40};
    Simulation sim(scene, State(s));
    sim.advance(5);
    return sim.sync();
  };
  const State builtin = with("opencl-binned", "double", "builtin");
  for (const char* exp : {"ranged", "native"}) {
    const State v = with("opencl-binned", "double", exp);
    EXPECT_LT(max_difference(builtin, v), std::string(exp) == "ranged" ? 1e-9 : 1e-3) << exp;
    EXPECT_EQ(v.hash(), with("opencl-allpairs", "double", exp).hash()) << exp;
  }
  const State single = with("opencl-binned", "float", "builtin");
  EXPECT_LT(max_difference(builtin, single), 1e-3);
  EXPECT_EQ(single.hash(), with("opencl-allpairs", "float", "builtin").hash());
}

// Final positions of `steps` steps on a 200 um box (22^3 bins), or the state frozen
// at the failing step when the run stops.
State run_wide(const std::string& backend, const std::string& precision, State s, long steps,
               const std::string& skin = "1") {
  auto scene = scene_from(testing::kMechanicsYaml, {"backend.name=" + backend, "backend.precision=" + precision,
                                                    "backend.opencl-binned.skin=" + skin});
  scene.box_lo = {0, 0, 0};
  scene.box_hi = {200, 200, 200};
  Simulation sim(scene, std::move(s));
  try {
    sim.advance(steps);
  } catch (const SimulationError&) {
  }
  return sim.sync();
}

// The binned force kernel masks a row's candidates 64 at a time and evaluates the set bits; the pairs must stay
// exactly those of all-pairs: a crowded clump (about 300 neighbours each, rows of several chunks), elements
// beyond the box (clamped into edge bins), and a non-finite element (which meets every element of its
// stencil, as in semlb_pair_force).
TEST(Backends, BinnedMaskKeepsExactlyTheAllPairsPairs) {
  const auto backends = available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end())
    GTEST_SKIP() << "no OpenCL platform";
  auto crowded = random_state(1500, 4, 200.0, 21);
  const auto clump = random_state(30, 10, 6.0, 22);  // 300 elements within 6 um of (97, 97, 97)
  for (size_t i = 0; i < clump.position.size(); ++i) crowded.position[i] = clump.position[i] + 97.0;
  auto outside = random_state(1500, 4, 260.0, 23);
  for (double& x : outside.position) x -= 30.0;  // 30 um beyond the box on every side
  auto nonfinite = random_state(1500, 4, 200.0, 24);
  for (int c = 0; c < 3; ++c) nonfinite.position[3 * 101 + c] = nonfinite.position[3 * 100 + c] + 0.5;
  nonfinite.position[3 * 100] = std::nan("");
  nonfinite.position[3 * 200 + 1] = INFINITY;
  for (const char* precision : {"float", "double"})
    for (const auto& [name, s] : {std::pair{"crowded", crowded}, {"outside", outside}}) {
      const State all = run_wide("opencl-allpairs", precision, s, 2);
      for (const char* skin : {"0", "1"})  // the stencil over fresh bins, and the neighbour list
        EXPECT_EQ(all.hash(), run_wide("opencl-binned", precision, s, 2, skin).hash())
            << name << " " << precision << " skin " << skin;
      EXPECT_NE(all.hash(), s.hash()) << name;  // the forces moved something
    }
  // All-pairs pairs a NaN element with every element, a binned backend with its stencil only: compare the
  // device's binned kernel with the C++ binned backend (same stencil); the NaN's partners take the clamped
  // force (a 1e4 um step), the others agree to 1e-9 um. (With a neighbour list a NaN element meets the elements
  // of the list's bins, of edge cutoff + skin: other partners, so the stencil is compared here.)
  const State host = run_wide("cpu-binned", "double", nonfinite, 2),
              device = run_wide("opencl-binned", "double", nonfinite, 2, "0");
  long partners = 0;
  for (size_t i = 0; i < host.position.size(); ++i) {
    const double a = host.position[i], b = device.position[i];
    if (!std::isfinite(a) || !std::isfinite(b))
      EXPECT_EQ(std::isnan(a) ? 0.0 : a, std::isnan(b) ? 0.0 : b) << i;
    else
      EXPECT_NEAR(a, b, 1e-9) << i;
    partners += std::abs(a - nonfinite.position[i]) > 100;
  }
  EXPECT_GT(partners, 3);
}

// The ghost exchange's device side: the x range and the bands beyond a plane, in element order, with the
// type only; 12,000 elements span 47 scan blocks. Positions are exact in double and rounded in float.
TEST(Backends, GhostBandsAndXRangeMatchTheHostState) {
  const auto s = random_state(3000, 4, 200.0, 16);
  for (const auto& name : available_backends())
    for (const char* precision : {"double", "float"}) {
      BackendConfig c;
      c.name = name;
      c.precision = precision;
      const auto b = make_backend(c);
      b->upload(s);
      const double tol = std::string(precision) == "float" ? 1e-4 : 0.0;
      const auto [lo, hi] = b->x_extent();
      double want_lo = 1e300, want_hi = -1e300;
      for (long e = 0; e < s.elements(); ++e)
        want_lo = std::min(want_lo, s.position[3 * e]), want_hi = std::max(want_hi, s.position[3 * e]);
      EXPECT_NEAR(lo, want_lo, tol) << name << " " << precision;
      EXPECT_NEAR(hi, want_hi, tol) << name << " " << precision;
      // both bands apart, one side only, neither, and overlapping bands (elements in both, listed in each)
      for (auto [below, above] : {std::pair{30.0, 170.0}, std::pair{-1.0, double{INFINITY}},
                                  std::pair{-double{INFINITY}, 100.0}, std::pair{120.0, 80.0}}) {
        Ghosts down, up;
        b->bands(below, above, down, up);
        for (auto [band, is_below] : {std::pair{&down, true}, std::pair{&up, false}}) {
          const double x = is_below ? below : above;
          std::vector<long> want;
          for (long e = 0; e < s.elements(); ++e)
            if (is_below ? s.position[3 * e] < x : s.position[3 * e] > x) want.push_back(e);
          ASSERT_EQ(band->elements(), static_cast<long>(want.size())) << name << " " << precision << " x " << x;
          const auto keys = s.element_keys();
          const auto info = s.element_info();
          for (size_t k = 0; k < want.size(); ++k) {
            ASSERT_EQ(band->keys[k], keys[want[k]]) << name << " " << precision << " element order";
            EXPECT_EQ(band->info[k], phys64::semlb_info_type(info[want[k]]));
            for (int d = 0; d < 3; ++d) EXPECT_NEAR(band->position[3 * k + d], s.position[3 * want[k] + d], tol);
          }
        }
      }
    }
}

// The split of the pair forces (local: owned on owned; non-local: ghosts on owned) is exact: on a tissue cut into
// owned cells (x below the middle) and ghost cells, local + non-local moves every owned element exactly as the
// whole tissue on one device does, in either order; without the non-local part it differs (the ghosts matter).
TEST(Backends, LocalPlusNonLocalEqualsTheFullPairForcesBitForBit) {
  const auto tissue = random_state(400, 8, 60.0, 21);
  State owned, ghost_cells;
  for (long c = 0; c < tissue.cells(); ++c) copy_cell(tissue, c, centroid(tissue, c)[0] < 30.0 ? owned : ghost_cells);
  owned.reindex();
  ghost_cells.reindex();
  ASSERT_GT(owned.cells(), 50);
  ASSERT_GT(ghost_cells.cells(), 50);
  Ghosts ghosts;  // numbered after the owned cells, as the ghost exchange does
  ghosts.position = ghost_cells.position;
  ghosts.keys = ghost_cells.element_keys();
  for (int info : ghost_cells.element_info())
    ghosts.info.push_back(phys64::semlb_info_pack(static_cast<int>(owned.cells()) + phys64::semlb_info_cell(info),
                                                  phys64::semlb_info_type(info)));
  auto scene = scene_from(testing::kMechanicsYaml, {});
  const Grid grid = Grid::cover({0, 0, 0}, {60, 60, 60}, scene.cutoff);
  const PairForces table =
      testing::pair_forces("mechanics", testing::kTypedMorse, scene.cutoff);  // intra apart from inter
  ASSERT_FALSE(table.params.empty());
  const long n = owned.elements();
  for (const auto& name : available_backends())
    for (const char* precision : {"double", "float"}) {
      BackendConfig c;
      c.name = name;
      c.precision = precision;
      // 0: whole tissue owned; 1: local, ghosts set, non-local (a decomposed step's order); 2: ghosts set,
      // non-local, local; 3: local only
      const auto step = [&](int how) {
        const auto b = make_backend(c);
        State out = how == 0 ? tissue : owned;
        b->upload(out);
        if (how >= 2) b->set_ghosts(ghosts);
        b->zero_forces();
        if (how == 0) b->pair_forces(table, grid);
        if (how == 1 || how == 3) b->pair_forces_local(table, grid);
        if (how == 1) b->set_ghosts(ghosts);
        if (how == 1 || how == 2) b->pair_forces_nonlocal(table, grid);
        if (how == 2) b->pair_forces_local(table, grid);
        b->integrate(0.01, 100.0, 0);
        b->download(out);
        std::vector<double> mine;  // the owned cells' elements, in the owned state's order
        if (how != 0) return out.position;
        for (long cell = 0; cell < out.cells(); ++cell)
          if (centroid(tissue, cell)[0] < 30.0)
            mine.insert(mine.end(), out.position.begin() + 3 * out.cell_first[cell],
                        out.position.begin() + 3 * (out.cell_first[cell] + out.cell_count[cell]));
        return mine;
      };
      const auto full = step(0);
      ASSERT_EQ(static_cast<long>(full.size()), 3 * n);
      EXPECT_EQ(step(1), full) << name << " " << precision;
      EXPECT_EQ(step(2), full) << name << " " << precision;
      EXPECT_NE(step(3), full) << name << " " << precision << ": the ghosts exert no force";
    }
}

// Cells of 8 elements with x uniform in [x0, x1) and y, z in [0, 60) um; cell ids start at id0 (distinct sets).
State slab_cells(long cells, double x0, double x1, uint64_t seed, uint64_t id0) {
  State s = random_state(cells, 8, 1.0, seed);
  for (long e = 0; e < s.elements(); ++e) {
    s.position[3 * e] = x0 + (x1 - x0) * s.position[3 * e];
    s.position[3 * e + 1] *= 60.0;
    s.position[3 * e + 2] *= 60.0;
  }
  for (auto& id : s.cell_id) id += id0;
  return s;
}

// The non-local forces visit only the owned elements of the bands' selection (Backend::bands: those within
// reach of a neighbour, the set a rank sends) and stay exact: a slab of owned cells with ghost cells beyond one
// side (the band is a quarter of the slab) and a slab narrower than two reaches with ghosts on both sides
// (elements in both bands, visited once). Local + non-local equals the whole tissue on one device bit for bit, and
// the non-local kernel's items are the bands' elements: a regression to every owned element fails here.
TEST(Backends, NonLocalForcesVisitOnlyTheBandsAndStayExact) {
  const double cutoff = 8.75, reach = cutoff * 1.01;  // the decomposed run's reach (kGhostSlack)
  struct Layout {
    double owned_lo, owned_hi, ghost_below, ghost_above;  // ghosts in [ghost_below, owned_lo), [owned_hi, ghost_above)
  };
  const PairForces table = testing::pair_forces("mechanics", testing::kTypedMorse, cutoff);  // as in the split test
  for (const Layout l : {Layout{0, 40, 0, 60}, Layout{20, 35, 5, 50}}) {
    const State owned = slab_cells(300, l.owned_lo, l.owned_hi, 31, 0);
    State ghost_cells, tissue = owned;  // the whole tissue: the owned cells first, as the ghosts are numbered
    if (l.owned_lo > l.ghost_below) ghost_cells = slab_cells(150, l.ghost_below, l.owned_lo, 32, 7000);
    const State above = slab_cells(150, l.owned_hi, l.ghost_above, 33, 14000);
    for (long c = 0; c < above.cells(); ++c) copy_cell(above, c, ghost_cells);
    ghost_cells.reindex();
    for (long c = 0; c < ghost_cells.cells(); ++c) copy_cell(ghost_cells, c, tissue);
    tissue.reindex();
    Ghosts ghosts;
    ghosts.position = ghost_cells.position;
    ghosts.keys = ghost_cells.element_keys();
    for (int info : ghost_cells.element_info())
      ghosts.info.push_back(phys64::semlb_info_pack(static_cast<int>(owned.cells()) + phys64::semlb_info_cell(info),
                                                    phys64::semlb_info_type(info)));
    const double below = l.owned_lo > l.ghost_below ? l.owned_lo + reach : -INFINITY, above_x = l.owned_hi - reach;
    long want_items = 0, want_union = 0;  // elements in the lower band plus those in the upper one; in either
    for (long e = 0; e < owned.elements(); ++e) {
      const bool d = owned.position[3 * e]<below, u = owned.position[3 * e]> above_x;
      want_items += d + u;
      want_union += d || u;
    }
    const long n = owned.elements();
    ASSERT_GT(want_items, 0);
    if (l.owned_lo == 0) {
      ASSERT_LT(want_items, n / 2) << "the band is a small part of the slab";
    } else {
      ASSERT_GT(want_items, want_union) << "some elements lie in both bands";
    }
    const Grid grid = Grid::cover({l.owned_lo - cutoff, 0, 0}, {l.owned_hi + cutoff, 60, 60}, cutoff);
    for (const auto& name : available_backends())
      for (const char* precision : {"double", "float"}) {
        BackendConfig c;
        c.name = name;
        c.precision = precision;
        const std::string kernel = name == "opencl-allpairs" ? "forces_allpairs" : "forces_nonlocal";
        // 0: the whole tissue; 1: bands selected, local, ghosts set, non-local (a decomposed step); 2: the same
        // without a selection (every owned element)
        const auto step = [&](int how, long* items) {
          const auto b = make_backend(c);
          State out = how == 0 ? tissue : owned;
          b->upload(out);
          Ghosts down, up;
          if (how == 1) {
            b->bands(below, above_x, down, up);
            EXPECT_EQ(down.elements() + up.elements(), want_items) << name << " " << precision;
          }
          b->zero_forces();
          if (how == 0) b->pair_forces(table, grid);
          if (how != 0) {
            b->pair_forces_local(table, grid);
            b->set_ghosts(ghosts);
            const auto before = b->launch_items().count(kernel) ? b->launch_items().at(kernel) : 0L;
            b->pair_forces_nonlocal(table, grid);
            *items = b->launch_items().at(kernel) - before;
          }
          b->integrate(0.01, 100.0, 0);
          b->download(out);
          out.position.resize(3 * n);  // the owned cells' elements come first in the whole tissue too
          return out.position;
        };
        long items = 0, all_items = 0;
        const auto full = step(0, &items);
        EXPECT_EQ(step(1, &items), full) << name << " " << precision << " with the bands' selection";
        // OpenCL launches one item per band slot (an element in both bands idles in its second); C++ loops the union
        EXPECT_EQ(items, name.rfind("opencl", 0) == 0 ? want_items : want_union)
            << name << " " << precision << ": the non-local kernel's items";
        EXPECT_EQ(step(2, &all_items), full) << name << " " << precision << " over every owned element";
        EXPECT_EQ(all_items, n) << name << " " << precision;
      }
  }
}

TEST(Backends, ResultsDoNotDependOnThreadCount) {
  const auto s = random_state(80, 10, 40.0, 13);
  EXPECT_EQ(run("cpu-binned", "double", s, 4, 1).hash(), run("cpu-binned", "double", s, 4, 2).hash());
}

TEST(Backends, ResultsDoNotDependOnCellOrder) {
  const auto s = random_state(50, 8, 40.0, 14);
  State reversed = s;  // the same tissue with the cells stored in reverse order
  reversed.position.clear();
  for (long c = s.cells() - 1; c >= 0; --c)
    reversed.position.insert(reversed.position.end(), s.position.begin() + 3 * s.cell_first[c],
                             s.position.begin() + 3 * (s.cell_first[c] + s.cell_count[c]));
  std::reverse(reversed.cell_id.begin(), reversed.cell_id.end());
  std::reverse(reversed.cell_type.begin(), reversed.cell_type.end());
  std::reverse(reversed.cell_count.begin(), reversed.cell_count.end());
  reversed.reindex();
  for (const auto& backend : available_backends()) {
    const State a = run(backend, "double", s, 3), b = run(backend, "double", reversed, 3);
    for (long c = 0; c < a.cells(); ++c) {
      const long rc = a.cells() - 1 - c;
      for (int k = 0; k < 3 * a.cell_count[c]; ++k)
        ASSERT_EQ(a.position[3 * a.cell_first[c] + k], b.position[3 * b.cell_first[rc] + k]) << backend;
    }
  }
}

// The exact kernels of 10 steps, per backend: the element stage of the listed effects (the binning kernels of
// the binned backends included), nothing of an unlisted effect, no ghost exchange, and no cell stage.
TEST(Backends, UnlistedEffectsLaunchNothing) {
  using Launches = std::map<std::string, long>;
  const std::map<std::string, Launches> forces = {
      {"serial", {{"forces_allpairs", 10}}},
      {"cpu-binned", {{"bin_sort", 10}, {"forces_binned", 10}}},
      {"opencl-allpairs", {{"forces_allpairs", 10}}},
      // (the default skin 0: no neighbour list; with one:
      // NeighbourList.LaunchesTheGatedBuildEveryStepAndTheCheckAfterTheFirst)
      {"opencl-binned",
       {{"bin_count", 10},
        {"scan_blocks", 10},
        {"scan_sums", 10},
        {"scan_add", 10},
        {"scatter", 10},
        {"forces_binned", 10}}}};
  for (const auto& backend : available_backends())
    for (const bool extra : {false, true}) {  // mechanics only; then with membrane and noise listed too
      std::vector<std::string> sets = {"backend.name=" + backend};
      if (extra) sets.insert(sets.end(), {"effects.membrane={}", "effects.noise={}"});
      auto scene = scene_from(testing::kMechanicsYaml, sets);
      scene.box_lo = {0, 0, 0};
      scene.box_hi = {40, 40, 40};
      Simulation sim(scene, random_state(10, 5, 40.0, 1));
      sim.advance(10);
      Launches want = forces.at(backend);
      want["zero_forces"] = want["integrate"] = 10;
      if (extra) want["membrane"] = want["noise"] = 10;
      EXPECT_EQ(sim.backend().launches(), want) << backend << (extra ? " with membrane and noise" : "");
      if (extra) continue;
      EXPECT_TRUE(sim.host_state().cell_fields.empty()) << backend;  // no growth/differentiation state
      EXPECT_EQ(sim.phases(), std::vector<std::string>({"mechanics", "integrate"})) << backend;
      EXPECT_FALSE(sim.has_cell_effects()) << backend;
      for (const auto& [part, seconds] : sim.cell_stage_seconds())  // stage, grid: never run
        EXPECT_EQ(seconds, 0.0) << backend << " " << part;
      EXPECT_EQ(sim.cell_stage_seconds().size(), 2u) << backend;
    }
}

// A scene with cell effects runs the cell stage every cell update: on OpenCL as device kernels (differentiation's
// fate kernel only when it is listed), on the C++ backends as the host reference; a scene without them launches none
// (UnlistedEffectsLaunchNothing compares the whole map).
TEST(Backends, CellEffectsLaunchTheCellStage) {
  const std::vector<std::string> cell_kernels = {"cells_plan", "cells_rewrite", "fate_differentiation", "cell_stage"};
  for (const auto& backend : available_backends())
    for (const bool differentiation : {false, true}) {
      std::vector<std::string> sets = {"backend.name=" + backend, "effects.growth={}", "effects.division={}"};
      if (differentiation) sets.push_back("effects.differentiation={}");
      auto scene = scene_from(testing::kMechanicsYaml, sets);
      scene.box_lo = {0, 0, 0};
      scene.box_hi = {40, 40, 40};
      Simulation sim(scene, random_state(10, 5, 40.0, 1));
      sim.advance(30);  // three cell updates
      const auto& l = sim.backend().launches();
      const auto n = [&](const std::string& k) { return l.count(k) ? l.at(k) : 0L; };
      const bool device = backend.rfind("opencl", 0) == 0;
      EXPECT_EQ(n("cells_plan"), device ? 3 : 0) << backend;
      EXPECT_EQ(n("cells_rewrite"), device ? 3 : 0) << backend;
      EXPECT_EQ(n("fate_differentiation"), device && differentiation ? 3 : 0) << backend;
      EXPECT_EQ(n("cell_stage"), device ? 0 : 3) << backend;
      double stage = 0;
      for (const auto& [part, seconds] : sim.cell_stage_seconds()) stage += seconds;
      EXPECT_GT(stage, 0.0) << backend;
    }
  auto plain = scene_from(testing::kMechanicsYaml);
  plain.box_lo = {0, 0, 0};
  plain.box_hi = {40, 40, 40};
  for (const auto& backend : available_backends()) {
    plain.backend.name = backend;
    Simulation sim(plain, random_state(10, 5, 40.0, 1));
    sim.advance(30);
    for (const auto& k : cell_kernels) EXPECT_EQ(sim.backend().launches().count(k), 0u) << backend << " " << k;
  }
}

// SEMLB_OPENCL_CAPTURE writes the first launch of the named kernel (KERNEL@N: the N-th) for replay under Nsight
// Compute (scripts/gpu/ncu_replay.cpp): the program binary, the NDRange, every argument in order with its kind, each
// buffer before and after the launch; other launches are not captured; a malformed value or launch number, an
// unknown kernel and a folder that cannot be made are refused naming the variable.
TEST(Backends, KernelCaptureWritesOneLaunchForReplay) {
  const auto backends = available_backends();
  if (std::find(backends.begin(), backends.end(), "opencl-binned") == backends.end())
    GTEST_SKIP() << "no OpenCL platform";
  const std::string dir = test::fresh_dir("kernel_capture");
  const auto s = random_state(40, 9, 40.0, 21);
  const State out = [&] {
    const test::ScopedEnv capture("SEMLB_OPENCL_CAPTURE", "forces_binned:" + dir);
    return run("opencl-binned", "float", s, 3, 0, 40, "0");  // the stencil kernel (no neighbour list)
  }();
  EXPECT_EQ(out.hash(), run("opencl-binned", "float", s, 3, 0, 40, "0").hash());  // capturing changes nothing
  std::ifstream launch(dir + "/launch.txt");
  std::vector<std::string> lines;
  for (std::string line; std::getline(launch, line);) lines.push_back(line);
  const long n = static_cast<long>(s.position.size() / 3);
  const std::vector<std::string> want = {"kernel forces_binned",
                                         "global " + std::to_string((n + 127) / 128 * 128),
                                         "group 128",
                                         "arg 0 buffer",
                                         "arg 1 buffer",
                                         "arg 2 buffer",
                                         "arg 3 buffer",
                                         "arg 4 value 16",
                                         "arg 5 value 16",
                                         "arg 6 value 16",
                                         "arg 7 buffer",
                                         "arg 8 value 4",
                                         "arg 9 buffer",
                                         "arg 10 buffer",
                                         "arg 11 value 4",
                                         "arg 12 value 4"};
  ASSERT_EQ(lines.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(lines[i].rfind(want[i], 0), 0u) << lines[i];
  const auto bytes = [&](const std::string& name) {
    std::ifstream f(dir + "/" + name, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  };
  EXPECT_FALSE(bytes("program.bin").empty());
  const std::vector<char> count = bytes("arg11.bin");  // n: the elements of the launch
  ASSERT_EQ(count.size(), 4u);
  int32_t items = 0;
  std::memcpy(&items, count.data(), 4);
  EXPECT_EQ(items, n);
  // The force buffer is the one the launch wrote: zero before, the pair forces after; the positions are unchanged.
  const std::vector<char> before = bytes("arg9.bin"), after = bytes("arg9.after.bin");
  ASSERT_GE(before.size(), static_cast<size_t>(3 * n * 8));
  EXPECT_TRUE(std::all_of(before.begin(), before.begin() + 3 * n * 8, [](char c) { return c == 0; }));
  EXPECT_NE(before, after);
  EXPECT_EQ(bytes("arg0.bin"), bytes("arg0.after.bin"));
  // KERNEL@N captures the N-th launch instead: the third step's positions, not the first's.
  const std::string third = test::fresh_dir("kernel_capture_3");
  {
    const test::ScopedEnv capture("SEMLB_OPENCL_CAPTURE", "forces_binned@3:" + third);
    run("opencl-binned", "float", s, 3, 0, 40, "0");
  }
  std::ifstream third_pos(third + "/arg0.bin", std::ios::binary);
  const std::vector<char> pos3((std::istreambuf_iterator<char>(third_pos)), std::istreambuf_iterator<char>());
  ASSERT_EQ(pos3.size(), bytes("arg0.bin").size());
  EXPECT_NE(pos3, bytes("arg0.bin"));
  for (const std::string& bad :
       std::vector<std::string>{"forces_binned", "no_such_kernel:" + dir + "/x", "forces_binned:/proc/no/such",
                                "forces_binned@0:" + dir, "forces_binned@2x:" + dir, "@2:" + dir}) {
    const test::ScopedEnv capture("SEMLB_OPENCL_CAPTURE", bad);
    try {
      run("opencl-binned", "float", s, 1);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("SEMLB_OPENCL_CAPTURE"), std::string::npos) << e.what();
    }
  }
}

TEST(Backends, UnknownBackendIsRefusedWithTheKnownOnes) {
  auto scene = scene_from(testing::kMechanicsYaml, {"backend.name=cuda"});
  try {
    Simulation sim(scene, random_state(2, 2, 5.0, 1));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("known: cpu-binned"), std::string::npos) << e.what();
  }
}

// Each backend reads its own keys of the scene's `backend` map (backend_settings): beside name and precision for the
// chosen one, and in its own map `backend.NAME` (checked whichever backend runs); a key it does not use is an
// InputError naming the file, line and field.
TEST(Backends, EachBackendReadsItsOwnSettingsAndRefusesTheOthers) {
  std::string yaml = testing::kMechanicsYaml;
  yaml.erase(yaml.find("backend:"), yaml.find('\n', yaml.find("backend:")) + 1 - yaml.find("backend:"));
  yaml += "backend:\n  name: NAME\n  KEY: VALUE\n";
  const auto settings = [&](const std::string& name, const std::string& key, const std::string& value) {
    std::string y = yaml;
    y.replace(y.find("NAME"), 4, name);
    y.replace(y.find("KEY"), 3, key);
    y.replace(y.find("VALUE"), 5, value);
    return backend_settings(scene_from(y).backend);
  };
  const auto refused = [&](const std::string& name, const std::string& key, const std::string& value) {
    try {
      settings(name, key, value);
      return std::string("accepted");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
  };
  EXPECT_EQ(settings("cpu-binned", "threads", "3").threads, 3);
  EXPECT_EQ(settings("opencl-allpairs", "platform", "Portable").platform, "Portable");
  EXPECT_EQ(settings("opencl-binned", "device", "1").device, 1);
  EXPECT_EQ(settings("opencl-binned", "skin", "0.5").skin, 0.5);
  // pair_exp: the precision's default, a choice, a bad value, and ranged refused in float where it runs (a scene for
  // several backends may keep it in a backend's map)
  EXPECT_EQ(settings("opencl-binned", "device", "1").pair_exp, "ranged");
  EXPECT_EQ(settings("opencl-allpairs", "pair_exp", "ranged").pair_exp, "ranged");
  const auto in_float = [&](const std::string& key, const std::string& value,
                            const std::string& name = "opencl-binned") {
    std::string y = yaml;
    y.replace(y.find("NAME"), 4, name);
    y.replace(y.find("KEY"), 3, key);
    y.replace(y.find("VALUE"), 5, value);
    return backend_settings(scene_from(y, {"backend.precision=float"}).backend);
  };
  EXPECT_EQ(in_float("device", "0").pair_exp, "native");
  EXPECT_EQ(in_float("pair_exp", "builtin").pair_exp, "builtin");
  EXPECT_EQ(in_float("opencl-binned", "{pair_exp: ranged}", "cpu-binned").name, "cpu-binned");
  // the key a backend does not use: named with the file and line, whichever backend it is another's
  const int line = static_cast<int>(std::count(yaml.begin(), yaml.begin() + yaml.find("KEY"), '\n')) + 1;
  const std::string at = "test.yaml:" + std::to_string(line) + ": field 'backend.";
  EXPECT_EQ(refused("cpu-binned", "skin", "0.5"), at + "skin': backend 'cpu-binned' does not use it");
  EXPECT_EQ(refused("serial", "threads", "1"), at + "threads': backend 'serial' does not use it");
  EXPECT_EQ(refused("cpu-binned", "platform", "Portable"), at + "platform': backend 'cpu-binned' does not use it");
  EXPECT_EQ(refused("opencl-allpairs", "skin", "0.5"), at + "skin': backend 'opencl-allpairs' does not use it");
  EXPECT_EQ(refused("opencl-binned", "threads", "1"), at + "threads': backend 'opencl-binned' does not use it");
  EXPECT_EQ(refused("cpu-binned", "pair_exp", "builtin"), at + "pair_exp': backend 'cpu-binned' does not use it");
  EXPECT_EQ(refused("opencl-binned", "pair_exp", "fast"), at + "pair_exp': 'fast' is not builtin, ranged or native");
  EXPECT_EQ(refused("cpu-binned", "opencl-allpairs", "{pair_exp: libm}"),
            at + "opencl-allpairs.pair_exp': 'libm' is not builtin, ranged or native");
  try {
    in_float("pair_exp", "ranged");
    ADD_FAILURE() << "ranged accepted in float";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              at + "pair_exp': ranged is a double exp: in float use native (the default) or builtin");
  }
  EXPECT_NE(
      refused("cpu-binned", "cpu-binnd", "{threads: 1}").find("field 'backend.cpu-binnd': is not a backend (known: "),
      std::string::npos);
  // a backend's own map: applied when it runs, checked when another does; the flat keys override it
  EXPECT_EQ(settings("opencl-binned", "opencl-binned", "{skin: 0.5}").skin, 0.5);
  EXPECT_EQ(settings("cpu-binned", "opencl-binned", "{skin: 0.5}").skin, 0.0);
  EXPECT_EQ(settings("cpu-binned", "cpu-binned", "{threads: 2}").threads, 2);
  EXPECT_EQ(refused("cpu-binned", "opencl-binned", "{threads: 1}"),
            at + "opencl-binned.threads': backend 'opencl-binned' does not use it");
  EXPECT_EQ(refused("cpu-binned", "serial", "{threads: 1}"), at + "serial.threads': backend 'serial' does not use it");
  EXPECT_NE(refused("cpu-binned", "threads", "-1").find("threads"), std::string::npos);  // its range, as before
  EXPECT_EQ(
      backend_settings(scene_from(yaml.substr(0, yaml.find("backend:")) + "backend:\n  name: opencl-binned\n"
                                                                          "  skin: 1\n  opencl-binned: {skin: 0.5}\n")
                           .backend)
          .skin,
      1.0);
  // every shipped scene on every backend
  for (const char* file : {"scenes/epidermis.yaml", "scenes/mechanics.yaml", "scenes/epidermis_development.yaml"})
    for (const auto& name : Backends::names())
      EXPECT_NO_THROW(backend_settings(load_scene(test::source(file), {"backend.name=" + name}).backend))
          << file << " " << name;
}

TEST(Backends, OpenClPlatformIsChosenByNameNotIndex) {
  if (cl::list_devices().empty()) GTEST_SKIP() << "no OpenCL platform";
  EXPECT_THROW(cl::choose_device("no-such-platform", 0), InputError);
  EXPECT_THROW(cl::choose_device(cl::list_devices()[0].platform_name, 99), InputError);
  EXPECT_EQ(cl::choose_device(cl::list_devices()[0].platform_name.substr(0, 4), 0).platform_name,
            cl::list_devices()[0].platform_name);
}

}  // namespace
}  // namespace semlb::engine
