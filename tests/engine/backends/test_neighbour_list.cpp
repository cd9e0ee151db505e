// opencl-binned's neighbour list (skin, reuse, rebuild on the device) against all pairs, bit for bit: pairs just inside
// and outside the cutoff and cutoff + skin moved across half the skin, a division, and a wrong trigger being caught.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>

#include "engine/physics/cpu_physics.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"
#include "engine/simulation/simulation.hpp"
#include "../engine_fixtures.hpp"
#include "../kernel_program.hpp"
#include "../../run_command.hpp"

namespace semlb::engine {
namespace {

using testing::available_backends;
using testing::scene_from;

constexpr double kCutoff = 8.75, kSkin = 1.0;

bool have_opencl() {
  const auto b = available_backends();
  return std::find(b.begin(), b.end(), "opencl-binned") != b.end();
}

// 6 x 6 x 4 pair sites 30 um apart (no two sites within cutoff + skin + their drift); the pair at site k lies at a
// distance of cutoff + u skin along a random direction, u from {-1e-4, 1e-4, 1 - 1e-4, 1 + 1e-4} (just inside and
// just outside the cutoff and cutoff + skin) or uniform in [-0.5, 2]. A pair is one cell of two elements or two cells
// of one (the intra and the inter Morse sets).
State pair_sites(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(-0.5, 2.0);
  const double edges[] = {-1e-4, 1e-4, 1 - 1e-4, 1 + 1e-4};
  State s;
  int k = 0;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 6; ++x, ++k) {
        const double c[3] = {20.0 + 30 * x, 20.0 + 30 * y, 20.0 + 30 * z};
        double d[3] = {n(rng), n(rng), n(rng)};
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double r = kCutoff + kSkin * (k % 2 == 0 ? edges[(k / 2) % 4] : u(rng));
        for (double& v : d) v *= 0.5 * r / len;
        const bool one_cell = k % 3 == 0;
        for (int e = 0; e < 2; ++e) {
          if (e == 0 || !one_cell) {
            s.cell_id.push_back(static_cast<uint64_t>(2 * k + e));
            s.cell_type.push_back(k % 3);
            s.cell_count.push_back(one_cell ? 2 : 1);
          }
          for (int a = 0; a < 3; ++a) s.position.push_back(c[a] + (e == 0 ? d[a] : -d[a]));
        }
      }
  s.reindex();
  return s;
}

// mechanics with an inter-cell set per type pair (testing::kTypedMorse).
PairForces table() { return testing::pair_forces("mechanics", testing::kTypedMorse, kCutoff); }

struct Walk {
  std::vector<std::vector<int64_t>> forces;  // per step
  std::vector<long> within;                  // pairs within the cutoff per step (host brute force)
  ListStats list;
};

// `steps` steps of: the pair forces (read back), then Brownian moves of sigma um per coordinate (the noise kernel).
Walk walk(const std::string& backend, const std::string& precision, double skin, long steps, double sigma,
          bool newton = false, State s = pair_sites(7), int bin_divisions = 1) {
  BackendConfig c;
  c.name = backend;
  c.precision = precision;
  c.skin = skin;
  c.newton = newton;
  c.list_bin_divisions = bin_divisions;
  auto b = make_backend(c);
  b->upload(s);
  const Grid g = Grid::cover({0, 0, 0}, {200, 200, 140}, kCutoff);
  Walk w;
  for (long step = 0; step < steps; ++step) {
    b->zero_forces();
    b->pair_forces(table(), g);
    w.forces.push_back(b->fixed_forces());
    b->download(s);
    long within = 0;
    for (long i = 0; i < s.elements(); ++i)
      for (long j = i + 1; j < s.elements(); ++j) {
        double r2 = 0;
        for (int a = 0; a < 3; ++a)
          r2 += (s.position[3 * i + a] - s.position[3 * j + a]) * (s.position[3 * i + a] - s.position[3 * j + a]);
        within += r2 < kCutoff * kCutoff;
      }
    w.within.push_back(within);
    b->noise(sigma, 11, step);
  }
  w.list = b->list_stats();
  return w;
}

// Pairs cross the cutoff while the list is reused (the in-cutoff count changes between builds), and every step's
// forces equal all pairs' bit for bit, in both precisions, with the full list and the half one (newton).
TEST(NeighbourList, SeesExactlyTheAllPairsPairsWhileElementsMoveAcrossHalfTheSkin) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  for (const char* precision : {"double", "float"}) {
    const long steps = 80;
    const double sigma = kSkin / 20;
    const Walk all = walk("opencl-allpairs", precision, 0, steps, sigma);
    const Walk list = walk("opencl-binned", precision, kSkin, steps, sigma);
    const Walk half = walk("opencl-binned", precision, kSkin, steps, sigma, true);
    const Walk fresh = walk("opencl-binned", precision, 0, steps, sigma);  // bins every step
    ASSERT_EQ(all.forces.size(), list.forces.size());
    long changes = 0;
    for (long t = 0; t < steps; ++t) {
      EXPECT_EQ(list.forces[t], all.forces[t]) << precision << " step " << t;
      EXPECT_EQ(half.forces[t], all.forces[t]) << precision << " step " << t << " (newton)";
      EXPECT_EQ(fresh.forces[t], all.forces[t]) << precision << " step " << t;
      changes += t > 0 && all.within[t] != all.within[t - 1];
    }
    EXPECT_GT(changes, 10) << precision << ": pairs crossed the cutoff";
    EXPECT_EQ(list.list.skin, kSkin);
    EXPECT_GT(list.list.builds, 2) << precision << ": rebuilt as elements moved";
    EXPECT_LT(list.list.builds, steps / 3) << precision << ": and reused in between";
    EXPECT_EQ(fresh.list.builds, 0);
    EXPECT_TRUE(half.list.newton);
    EXPECT_EQ(half.list.builds, list.list.builds) << precision << ": the same rebuilds";
  }
}

// SEMLB_OPENCL_BUILD_OPTIONS with `extra` appended while it lives (a kernel variant of the backends built meanwhile).
class ExtraBuildOptions : public test::ScopedEnv {
 public:
  explicit ExtraBuildOptions(const std::string& extra)
      : ScopedEnv(
            "SEMLB_OPENCL_BUILD_OPTIONS",
            std::string(std::getenv("SEMLB_OPENCL_BUILD_OPTIONS") ? std::getenv("SEMLB_OPENCL_BUILD_OPTIONS") : "") +
                " " + extra) {}
};

// The same walk with the rebuild trigger at 3 skins instead of 0.49 (a build option of the kernels): pairs that
// enter the cutoff from beyond cutoff + skin are missed, and the comparison above catches it.
TEST(NeighbourList, AWrongTriggerMissesPairsAndIsCaught) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  const Walk list = [] {
    const ExtraBuildOptions trigger("-DSEMLB_NL_TRIGGER=3.0");
    return walk("opencl-binned", "double", kSkin, 80, kSkin / 20);
  }();
  const Walk all = walk("opencl-allpairs", "double", 0, 80, kSkin / 20);
  long wrong = 0;
  for (size_t t = 0; t < all.forces.size(); ++t) wrong += list.forces[t] != all.forces[t];
  EXPECT_EQ(list.list.builds, 1) << "built once, never rebuilt";
  EXPECT_GT(wrong, 0) << "a list never rebuilt must miss pairs, or this walk tests nothing";
}

// Growth and division change the elements at every cell stage: the list is rebuilt there and the run equals
// opencl-allpairs and opencl-binned without a list, bit for bit, in both precisions, with the full and the half list.
TEST(NeighbourList, RunsWithDivisionsEqualAllPairs) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  const std::string yaml = R"(
name: t
cutoff: 8.75
tissue: {cells: 30, layers: 2}
time: {dt: 0.01, steps: 60, cell_update_every: 5}
backend: {name: serial}
effects:
  mechanics: {}
  membrane: {}
  growth: {cycle_time: 0.3, types: [basal, spinous]}
  division: {at_elements: 14, types: [basal, spinous]}
  noise: {diffusion: 0.5}
)";
  for (const char* precision : {"double", "float"}) {
    std::map<std::string, State> out;
    long cells0 = 0, builds = 0;
    for (const std::string v : {"opencl-allpairs", "opencl-binned", "opencl-binned skin", "opencl-binned newton"}) {
      const bool list = v != "opencl-allpairs" && v != "opencl-binned";
      auto scene = scene_from(
          yaml, {"backend.name=" + v.substr(0, v.find(' ')), std::string("backend.precision=") + precision,
                 "backend.opencl-binned.skin=" + std::string(list ? "0.5" : "0"),
                 "backend.opencl-binned.newton=" + std::string(v == "opencl-binned newton" ? "true" : "false")});
      Simulation sim(scene, make_tissue(scene));
      cells0 = sim.host_state().cells();
      sim.advance(60);
      out[v] = sim.sync();
      if (v == "opencl-binned skin") builds = sim.backend().list_stats().builds;
    }
    EXPECT_GT(out["opencl-allpairs"].cells(), cells0 + 5) << precision << ": cells divided";
    EXPECT_EQ(out["opencl-binned skin"].hash(), out["opencl-allpairs"].hash()) << precision;
    EXPECT_EQ(out["opencl-binned newton"].hash(), out["opencl-allpairs"].hash()) << precision;
    EXPECT_EQ(out["opencl-binned"].hash(), out["opencl-allpairs"].hash()) << precision;
    EXPECT_GE(builds, 12) << precision << ": at least one build per cell stage that changed the elements";
  }
}

// 600 elements in a 25 um cube (60 cells of 10), up to 172 partners within cutoff + skin: the first builds find more
// than the 64 stored per element at first, so those slots take the stencil until kmax has grown; forces equal all
// pairs' throughout, with the full list and the half one (which lists fewer: each pair once).
TEST(NeighbourList, SlotsOverKmaxTakeTheStencilWithFullAndHalfLists) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  State dense = testing::random_state(60, 10, 25.0, 3);
  for (long i = 0; i < dense.elements(); ++i)
    for (int a = 0; a < 3; ++a) dense.position[3 * i + a] += 60;
  for (const char* precision : {"double", "float"}) {
    const Walk all = walk("opencl-allpairs", precision, 0, 12, 0.05, false, dense);
    long full_max = 0;
    for (bool newton : {false, true}) {
      const Walk list = walk("opencl-binned", precision, kSkin, 12, 0.05, newton, dense);
      for (size_t t = 0; t < all.forces.size(); ++t)
        EXPECT_EQ(list.forces[t], all.forces[t]) << precision << " newton " << newton << " step " << t;
      EXPECT_GT(list.list.max_partners, 64) << "over the first kmax, or the stencil path went untested";
      EXPECT_GE(list.list.kmax, list.list.max_partners) << "and kmax grew to hold them";
      if (newton)
        EXPECT_LT(list.list.max_partners, full_max) << "the half list holds each pair once";
      else
        full_max = list.list.max_partners;
    }
  }
}

// The variant that hands each work-group's slots to its items longest list first (-DSEMLB_NL_GROUP_SORT, sorted in
// local memory each launch): every slot still runs once, so the forces equal all pairs' bit for bit, with the full
// and the half list; 600 elements leave the last group of 128 partly empty, and the densest slots take the stencil.
// That the option reached the program: its nl_forces requires groups of 128 (reqd_work_group_size), the plain one not.
TEST(NeighbourList, SlotsSortedByListLengthInTheirGroupGiveTheSameForces) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  const auto compiled_group = [] {
    BackendConfig c;
    c.name = "opencl-binned";
    c.skin = kSkin;
    const testing::KernelProgram p(c, "");
    size_t group[3] = {0, 0, 0};
    cl::check(clGetKernelWorkGroupInfo(p.kernel("nl_forces").get(), p.device.device, CL_KERNEL_COMPILE_WORK_GROUP_SIZE,
                                       sizeof group, group, nullptr),
              "clGetKernelWorkGroupInfo");
    return group[0];
  };
  EXPECT_EQ(compiled_group(), 0u);
  {
    const ExtraBuildOptions sort("-DSEMLB_NL_GROUP_SORT");
    EXPECT_EQ(compiled_group(), 128u);
  }
  State dense = testing::random_state(60, 10, 25.0, 3);
  for (long i = 0; i < dense.elements(); ++i)
    for (int a = 0; a < 3; ++a) dense.position[3 * i + a] += 60;
  for (const char* precision : {"double", "float"}) {
    const Walk all = walk("opencl-allpairs", precision, 0, 12, 0.05, false, dense);
    const ExtraBuildOptions sort("-DSEMLB_NL_GROUP_SORT");
    for (bool newton : {false, true}) {
      const Walk list = walk("opencl-binned", precision, kSkin, 12, 0.05, newton, dense);
      for (size_t t = 0; t < all.forces.size(); ++t)
        EXPECT_EQ(list.forces[t], all.forces[t]) << precision << " newton " << newton << " step " << t;
      EXPECT_GT(list.list.max_partners, 64) << "slots over the first kmax took the stencil";
    }
  }
}

// The list's bins of edge (cutoff + skin) / 2 and / 3 (`list_bin_divisions`, the build over 125 or 343 bins): the
// same pairs listed, so the same forces as all pairs bit for bit and the same builds and partner counts as bins of
// edge cutoff + skin (and, with the full list, the same largest partner count), with the full and the half list; on the
// walk across the cutoff and on the dense tissue whose slots over kmax take the stencil (over the smaller bins too).
TEST(NeighbourList, SmallerBinsListTheSamePairs) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  State dense = testing::random_state(60, 10, 25.0, 3);
  for (long i = 0; i < dense.elements(); ++i)
    for (int a = 0; a < 3; ++a) dense.position[3 * i + a] += 60;
  struct Case {
    State tissue;
    long steps;
    double sigma;
  };
  const Case cases[] = {{pair_sites(7), 40, kSkin / 20}, {dense, 12, 0.05}};
  for (const char* precision : {"double", "float"})
    for (const auto& [tissue, steps, sigma] : cases) {
      const Walk all = walk("opencl-allpairs", precision, 0, steps, sigma, false, tissue);
      for (bool newton : {false, true}) {
        const Walk one = walk("opencl-binned", precision, kSkin, steps, sigma, newton, tissue);
        for (int divisions : {2, 3}) {
          const Walk small = walk("opencl-binned", precision, kSkin, steps, sigma, newton, tissue, divisions);
          for (long t = 0; t < steps; ++t)
            ASSERT_EQ(small.forces[t], all.forces[t])
                << precision << " newton " << newton << " divisions " << divisions << " step " << t;
          EXPECT_EQ(small.list.bin_divisions, divisions);
          EXPECT_EQ(small.list.builds, one.list.builds) << precision << " divisions " << divisions;
          if (!newton) {  // a half list's counts follow the slot order, which the bins set
            EXPECT_EQ(small.list.max_partners, one.list.max_partners) << precision << " divisions " << divisions;
          }
        }
      }
    }
}

// A wrong reach (the kernels' stencil of one bin each way over bins of half the list radius) misses partners, and
// the comparison above catches it.
TEST(NeighbourList, SmallerBinsWithTooShortAReachMissPairs) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  const Walk all = walk("opencl-allpairs", "double", 0, 10, kSkin / 20);
  const Walk wrong = [] {
    const ExtraBuildOptions reach("-DSEMLB_NL_REACH=1");  // after the backend's own =2: the last one holds
    return walk("opencl-binned", "double", kSkin, 10, kSkin / 20, false, pair_sites(7), 2);
  }();
  long differ = 0;
  for (size_t t = 0; t < all.forces.size(); ++t) differ += wrong.forces[t] != all.forces[t];
  EXPECT_GT(differ, 0);
}

TEST(NeighbourList, SkinIsANonNegativeLength) {
  const auto skin = [](const std::vector<std::string>& sets) {
    return backend_settings(scene_from(testing::kMechanicsYaml, sets).backend).skin;
  };
  EXPECT_THROW(skin({"backend.name=opencl-binned", "backend.skin=-1"}), InputError);
  EXPECT_THROW(skin({"backend.opencl-binned.skin=-1"}), InputError);  // checked whichever backend runs
  EXPECT_EQ(skin({"backend.name=opencl-binned", "backend.skin=0.5"}), 0.5);
  EXPECT_EQ(skin({"backend.name=opencl-binned", "backend.opencl-binned.skin=0.5"}), 0.5);
  EXPECT_EQ(skin({"backend.opencl-binned.skin=0.5"}), 0.0);  // cpu-binned: opencl-binned's map only checked
  EXPECT_EQ(skin({"backend.name=opencl-binned"}), 0.0);      // no list unless a scene asks for one
  const auto config = [](const std::vector<std::string>& sets) {
    return backend_settings(scene_from(testing::kMechanicsYaml, sets).backend);
  };
  EXPECT_TRUE(config({"backend.name=opencl-binned", "backend.skin=0.5", "backend.newton=true"}).newton);
  EXPECT_FALSE(config({"backend.name=opencl-binned", "backend.skin=0.5"}).newton);
  EXPECT_THROW(config({"backend.name=opencl-binned", "backend.newton=true"}), InputError);  // no list to halve
  EXPECT_THROW(config({"backend.name=opencl-binned", "backend.skin=0.5", "backend.newton=yes"}), InputError);
  // the list's settings are checked once both places are read: skin beside the map, newton in it, and the reverse
  EXPECT_TRUE(config({"backend.name=opencl-binned", "backend.skin=0.5", "backend.opencl-binned.newton=true"}).newton);
  EXPECT_TRUE(config({"backend.name=opencl-binned", "backend.opencl-binned.skin=0.5", "backend.newton=true"}).newton);
  EXPECT_EQ(config({"backend.name=opencl-binned", "backend.skin=0.5", "backend.opencl-binned.list_bin_divisions=2"})
                .list_bin_divisions,
            2);
  EXPECT_THROW(config({"backend.name=opencl-binned", "backend.skin=0", "backend.opencl-binned.skin=0.5",
                       "backend.opencl-binned.newton=true"}),
               InputError);                                                 // beside the map overrides it: no list
  EXPECT_THROW(config({"backend.opencl-binned.newton=true"}), InputError);  // checked whichever backend runs
  EXPECT_EQ(config({"backend.name=opencl-binned", "backend.skin=0.5"}).list_bin_divisions, 1);
  EXPECT_EQ(
      config({"backend.name=opencl-binned", "backend.skin=0.5", "backend.list_bin_divisions=2"}).list_bin_divisions, 2);
  EXPECT_THROW(config({"backend.name=opencl-binned", "backend.list_bin_divisions=2"}), InputError);  // no list
  EXPECT_THROW(config({"backend.name=opencl-binned", "backend.skin=0.5", "backend.list_bin_divisions=4"}), InputError);
  EXPECT_THROW(config({"backend.name=opencl-binned", "backend.skin=0.5", "backend.list_bin_divisions=1.5"}),
               InputError);
}

// What a step launches with the list: its check from the second step on (the first builds unasked), the gated build
// kernels every step (they return at once unless the check asked for a build), the list's force kernels; and with
// skin 0 the stencil over fresh bins every step, without the list's kernels.
TEST(NeighbourList, LaunchesTheGatedBuildEveryStepAndTheCheckAfterTheFirst) {
  if (!have_opencl()) GTEST_SKIP() << "no OpenCL platform";
  using Launches = std::map<std::string, long>;
  const Launches list = {{"nl_check", 9},   {"bin_count", 10},   {"scan_blocks", 10}, {"scan_sums", 10},
                         {"scan_add", 10},  {"scatter", 10},     {"nl_build", 10},    {"nl_done", 10},
                         {"nl_forces", 10}, {"nl_overflow", 10}, {"zero_forces", 10}, {"integrate", 10}};
  const Launches stencil = {{"bin_count", 10}, {"scan_blocks", 10},   {"scan_sums", 10},   {"scan_add", 10},
                            {"scatter", 10},   {"forces_binned", 10}, {"zero_forces", 10}, {"integrate", 10}};
  for (const auto& [skin, want] : {std::pair{"1", list}, {"0", stencil}}) {
    auto scene =
        scene_from(testing::kMechanicsYaml, {"backend.name=opencl-binned", std::string("backend.skin=") + skin});
    scene.box_lo = {0, 0, 0};
    scene.box_hi = {40, 40, 40};
    Simulation sim(scene, testing::random_state(10, 5, 40.0, 1));
    sim.advance(10);
    EXPECT_EQ(sim.backend().launches(), want) << "skin " << skin;
  }
}

}  // namespace
}  // namespace semlb::engine
