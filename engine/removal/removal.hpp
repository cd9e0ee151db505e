// Cell removal rules: at every cell stage a cell leaves the tissue when its rule says so from its centroid, type
// and element count (desquamation: cells above a height are shed), each written once as a C99 evaluator header
// (removal/NAME.h) and registered by name; the compaction is written once per backend kind (Backend::remove_cells:
// on the host for the C++ backends, on the device for OpenCL with the kernel template removal_rule.cl and the
// migration's cells_split).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "device/backend.hpp"
#include "model/scene.hpp"

namespace semlb::engine {

// A registered removal rule. Its name is its scene key (`effects.NAME`), the stem of its evaluator header
// removal/NAME.h and, prefixed `remove_`, its OpenCL kernel's name in launches(). removal/NAME.cpp includes
// removal/NAME.h inside namespace cellrules (cpu_physics.hpp) and registers cellrules::semlb_remove_NAME.
struct RemovalRule {
  static constexpr const char* kKind = "removal rule";
  static constexpr const char* kListed = "removal-rules";
  int order = 70;  // its place among the effects (effect.hpp EffectInfo::order): after the cell rules
  // The derived parameters (at most 64 doubles) from the scene's section; its errors name file, line and field.
  std::function<std::vector<double>(const Section&)> read;
  RemovalEvaluator removes = nullptr;
  // A valid section for it (YAML flow map): what the suites that iterate RemovalRules::names() run it with.
  std::string example = "{}";

  // Registering `name` (a C identifier) also registers the effect `name` (effect.hpp: a cell effect whose
  // after_cell_stage calls Backend::remove_cells). std::logic_error on a name that is not a C identifier.
  static void registering(const std::string& name, const RemovalRule& rule);
};
using RemovalRules = PluginKind<RemovalRule>;
// What the backend runs for the registered removal rule `rule` (its evaluator; `params` its derived parameters);
// std::logic_error for an unregistered rule.
RemovalCall removal_call(const std::string& rule, std::vector<double> params);

}  // namespace semlb::engine
