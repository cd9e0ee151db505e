// Growth laws: how many elements a cell adds at a cell stage (the growth effect, `effects.growth: {law: NAME, ...}`),
// each written once as a C99 evaluator header (growth/NAME.h) and registered by name; the stage around it (newborns
// placed at `offset` um from the centroid, the scans and the rewrite) is the core's (physics/cells.h), run on the
// host by the C++ backends and by the OpenCL kernel cells_plan, which calls the scene's law by its index.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "model/scene.hpp"

namespace semlb::engine {

// The births of one cell at a stage: its `type`, `count` elements, centroid[3] (um) before growth, the stage's `time`
// and the `elapsed` h since the last stage, `p` the law's derived parameters (GrowthLaw::read); `field` (in/out) the
// law's per-cell field (0 and discarded when it has none). Returns the elements to add now, >= 0, with count + births
// below kMaxSlots (a law that breaks that stops the run naming the cell). The C++ instantiation of
// `semlb_growth_NAME` of growth/NAME.h (double, as all cell bookkeeping, cells.h).
using GrowthEvaluator = int (*)(int type, int count, const double* centroid, double time, double elapsed,
                                const double* p, double* field);

// A registered growth law. Its name is the value of `effects.growth.law`, the stem of its header growth/NAME.h; the
// OpenCL kernels call it by its index in GrowthLaws::names() (the generated dispatch semlb_growth_law, in name order
// too). growth/NAME.cpp includes growth/NAME.h inside namespace cellrules (cpu_physics.hpp), registers its field (if
// any, "growth.WHAT": a field of the growth effect) with Registrar<CellFieldInfo> and the law.
struct GrowthLaw {
  static constexpr const char* kKind = "growth law";
  static constexpr const char* kListed = "growth-laws";
  // The derived parameters (at most SEMLB_CELL_RULE_PARAMS doubles) from the growth section, whose `law` and
  // `offset` keys are the effect's; its errors name file, line and field.
  std::function<std::vector<double>(const Section&)> read;
  GrowthEvaluator births = nullptr;
  std::string field;  // its per-cell field, or "" for none
  // The field's value for a cell of a new run (a state file's value is kept) from the parameters and a uniform draw
  // u in [0, 1) per cell (keyed by the cell id); nullptr: the field's registered initial value.
  std::function<double(const std::vector<double>& p, double u)> initial;
  // The length in h of the growth cycle (Effect::growth_phase, what the controllers see), or nullptr for none.
  std::function<double(const std::vector<double>& p)> cycle;
  // A valid growth section for it (YAML flow map, `law` included): what the suites that iterate GrowthLaws::names()
  // run it with.
  std::string example = "{}";

  // std::logic_error unless `name` is a C identifier.
  static void registering(const std::string& name, const GrowthLaw&) { check_plugin_name(kKind, name); }
};
using GrowthLaws = PluginKind<GrowthLaw>;

}  // namespace semlb::engine
