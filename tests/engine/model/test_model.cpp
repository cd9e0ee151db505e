// The model's layouts and names: element keys, packed element info, the named scene settings.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <stdexcept>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "engine/backends/backend.hpp"
#include "engine/physics/cpu_physics.hpp"
#include "engine/model/scene.hpp"
#include "engine/model/state.hpp"
#include "engine/io/io.hpp"
#include "engine/model/tissue.hpp"

namespace semlb::engine {
namespace {

TEST(Model, ElementKeysGiveBackTheirCellId) {
  std::set<uint64_t> keys;
  for (uint64_t id :
       {uint64_t{0}, uint64_t{1}, (uint64_t{1} << kRootIdBits) - 1, daughter_id(5, kMaxDivisionDepth - 1)})
    for (int slot : {0, 1, kMaxSlots - 1}) {
      EXPECT_EQ(cell_id_of_key(element_key(id, slot)), id) << id << " " << slot;
      keys.insert(element_key(id, slot));
    }
  EXPECT_EQ(keys.size(), 4u * 3u) << "keys are unique";
  EXPECT_LT(element_key(7, kMaxSlots - 1), element_key(8, 0)) << "a cell's keys are contiguous";
}

TEST(Model, ElementInfoPacksTheCellIndexAndType) {
  for (int cell : {0, 1, 12345, (1 << 28) - 1})
    for (int type = 0; type < kCellTypes; ++type) {
      const int info = phys64::semlb_info_pack(cell, type);
      EXPECT_EQ(phys64::semlb_info_cell(info), cell);
      EXPECT_EQ(phys64::semlb_info_type(info), type);
    }
  State s;
  s.cell_id = {10, 20};
  s.cell_type = {kGranular, kSpinous};
  s.cell_count = {2, 1};
  s.position.assign(9, 0.0);
  s.reindex();
  EXPECT_EQ(s.element_info(),
            (std::vector<int>{phys64::semlb_info_pack(0, kGranular), phys64::semlb_info_pack(0, kGranular),
                              phys64::semlb_info_pack(1, kSpinous)}));
}

// Every named setting reaches the scene field it names, with its value checked against its type.
TEST(Model, SceneSettingsSetTheirKeysWithTypedValues) {
  const std::vector<std::pair<std::string, std::string>> given = {{"cells", "40"},
                                                                  {"steps", "7"},
                                                                  {"dt", "0.005"},
                                                                  {"cutoff", "9.5"},
                                                                  {"seed", "3"},
                                                                  {"backend", "opencl-allpairs"},
                                                                  {"precision", "float"},
                                                                  {"platform", "Portable"},
                                                                  {"device", "2"},
                                                                  {"pair_exp", "builtin"},
                                                                  {"policy", "holt"},
                                                                  {"initial", "uniform"},
                                                                  {"rebalance_every", "25"},
                                                                  {"timing", "modelled"}};
  ASSERT_EQ(given.size(), scene_settings().size());
  std::vector<std::string> o;
  for (const auto& [name, value] : given) o.push_back(scene_override(name, value, "x: "));
  const Scene s = load_scene(std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml", o);
  EXPECT_EQ(s.tissue->integer("cells", 0, 0, 1000), 40);
  EXPECT_EQ(s.steps, 7);
  EXPECT_EQ(s.dt, 0.005);
  EXPECT_EQ(s.cutoff, 9.5);
  EXPECT_EQ(s.seed, 3u);
  EXPECT_EQ(s.backend.name, "opencl-allpairs");
  EXPECT_EQ(s.backend.precision, "float");
  const BackendConfig backend = backend_settings(s.backend);  // the backend's own keys, read by it
  EXPECT_EQ(backend.platform, "Portable");
  EXPECT_EQ(backend.device, 2);
  EXPECT_EQ(backend.pair_exp, "builtin");
  EXPECT_EQ(s.decomposition->text("policy", ""), "holt");
  EXPECT_EQ(s.decomposition->text("initial", ""), "uniform");
  EXPECT_EQ(s.decomposition->integer("rebalance_every", 0, 0, 1000), 25);
  EXPECT_EQ(s.decomposition->text("timing", ""), "modelled");

  try {
    scene_override("cells", "4e2", "--cells: ");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--cells: '4e2' is not an integer", 0), 0u) << e.what();
  }
  EXPECT_THROW(scene_override("dt", "fast", ""), InputError);
  EXPECT_EQ(scene_override("dt", "1e-3", ""), "time.dt=1e-3");
  EXPECT_EQ(scene_override("backend", "any text", ""), "backend.name=any text");
  EXPECT_THROW(scene_override("colour", "red", ""), std::logic_error);
}

// tissue.x_range keeps the cells whose centroid x lies in [lo, hi): together the two halves are the whole tissue.
TEST(Model, TissueXRangeKeepsOneSlabOfCells) {
  const std::string scene = std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml";
  Scene whole_scene = load_scene(scene, {"tissue.cells=60"});
  const State whole = make_tissue(whole_scene);
  long kept = 0;
  for (const auto& [lo, hi] : {std::pair{"-1e9", "25"}, std::pair{"25", "1e9"}}) {
    Scene half = load_scene(scene, {"tissue.cells=60", std::string("tissue.x_range=[") + lo + ", " + hi + "]"});
    const State s = make_tissue(half);
    ASSERT_GT(s.cells(), 0);
    for (long c = 0; c < s.cells(); ++c) {
      const double x = centroid(s, c)[0];
      EXPECT_GE(x, parse_real(lo, "lo"));
      EXPECT_LT(x, parse_real(hi, "hi"));
    }
    kept += s.cells();
  }
  EXPECT_EQ(kept, whole.cells());
  for (const std::string bad : {"[25, 0]", "[1]", "[1e9, 2e9]", "[a, 2]"}) {
    Scene s = load_scene(scene, {"tissue.cells=60", "tissue.x_range=" + bad});
    try {
      make_tissue(s);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("tissue.x_range"), std::string::npos) << e.what();
    }
  }
}

// The generator runs its two passes over the cells in parallel: 1, 2 and 3 threads give the same tissue bit for bit,
// and the same as its sequential definition for the first cell (elements at keys (cell << slot bits) | e).
TEST(Model, TissueIsTheSameOnAnyThreadCount) {
  Scene scene = load_scene(std::string(SEMLB_SOURCE_DIR) + "/scenes/epidermis.yaml", {"tissue.cells=997"});
  std::vector<State> made;
  const int before = omp_get_max_threads();
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    made.push_back(make_tissue(scene));
  }
  omp_set_num_threads(before);
  for (size_t k = 1; k < made.size(); ++k) {
    EXPECT_EQ(made[k].position, made[0].position) << k + 1 << " threads";
    EXPECT_EQ(made[k].cell_count, made[0].cell_count) << k + 1 << " threads";
    EXPECT_EQ(made[k].cell_type, made[0].cell_type) << k + 1 << " threads";
  }
  ASSERT_EQ(made[0].cells(), 997);
  long elements = 0;
  for (int n : made[0].cell_count) elements += n;
  EXPECT_EQ(made[0].elements(), elements);
  EXPECT_EQ(made[0].position.size(), static_cast<size_t>(3 * elements));
  for (double x : made[0].position) ASSERT_TRUE(std::isfinite(x));
}

// copy_cells (and canonical() through it) over more cells than its threads' threshold: each cell's id, type,
// count, positions and fields where the selection puts them, appended after what `to` held, on any thread count.
TEST(Model, CopyCellsPutsEachCellWhereTheSelectionSaysOnAnyThreadCount) {
  const long cells = 20000;
  State s;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<uint64_t> ids(cells);
  for (long c = 0; c < cells; ++c) ids[c] = static_cast<uint64_t>(c) * 7 + 3;
  std::shuffle(ids.begin(), ids.end(), rng);
  s.cell_fields["growth.volume"];
  for (long c = 0; c < cells; ++c) {
    s.cell_id.push_back(ids[c]);
    s.cell_type.push_back(static_cast<int>(c % 3));
    s.cell_count.push_back(1 + static_cast<int>(c % 5));
    s.cell_fields["growth.volume"].push_back(u(rng));
    for (int e = 0; e < 3 * s.cell_count.back(); ++e) s.position.push_back(u(rng));
  }
  s.reindex();
  std::vector<long> pick;  // every third cell, backwards
  for (long c = cells - 1; c >= 0; c -= 3) pick.push_back(c);
  const int before = omp_get_max_threads();
  std::vector<State> made;
  for (int threads : {1, 3}) {
    omp_set_num_threads(threads);
    State to = empty_like(s);
    copy_cells(s, {0, 1}, to);  // something already there
    copy_cells(s, pick, to);
    to.reindex();
    made.push_back(std::move(to));
  }
  omp_set_num_threads(before);
  const State& to = made[0];
  ASSERT_EQ(to.cells(), static_cast<long>(pick.size()) + 2);
  for (long k = 0; k < to.cells(); ++k) {
    const long c = k < 2 ? k : pick[k - 2];
    ASSERT_EQ(to.cell_id[k], s.cell_id[c]) << k;
    ASSERT_EQ(to.cell_type[k], s.cell_type[c]) << k;
    ASSERT_EQ(to.cell_count[k], s.cell_count[c]) << k;
    ASSERT_EQ(to.cell_fields.at("growth.volume")[k], s.cell_fields.at("growth.volume")[c]) << k;
    for (int e = 0; e < 3 * s.cell_count[c]; ++e)
      ASSERT_EQ(to.position[3 * to.cell_first[k] + e], s.position[3 * s.cell_first[c] + e]) << k;
  }
  EXPECT_EQ(made[1].position, to.position);
  EXPECT_EQ(made[1].cell_id, to.cell_id);
  EXPECT_EQ(made[1].cell_fields, to.cell_fields);
  const State sorted = s.canonical();
  EXPECT_TRUE(sorted.is_canonical());
  EXPECT_EQ(sorted.elements(), s.elements());
}

// A step count the device kernels cannot count (32 bits) is refused when the scene is read, never met mid-run.
TEST(Model, StepsBeyondWhatTheKernelsCountAreRefusedAtReadTime) {
  const std::string yaml = "name: t\ntissue: {cells: 4}\neffects: {mechanics: {}}\n";
  EXPECT_EQ(parse_scene(yaml, "t.yaml", {"time.steps=2147483647"}).steps, 2147483647L);
  try {
    parse_scene(yaml, "t.yaml", {"time.steps=2147483648"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("time.steps"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace semlb::engine
