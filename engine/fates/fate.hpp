// Cell fate rules: at every cell stage, after growth and division, a cell may change its type from its centroid,
// element count, its own per-cell field and the time since the last stage (differentiation: basal -> spinous ->
// granular), each written once as a C99 evaluator header (fates/NAME.h) and registered by name; the loop over the
// cells is written once per backend kind (Backend::cell_fate: on the host for the C++ backends, the OpenCL kernel
// template fate_rule.cl on the device).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "device/backend.hpp"
#include "model/scene.hpp"

namespace semlb::engine {

// A registered fate rule. Its name is its scene key (`effects.NAME`), the stem of its evaluator header fates/NAME.h
// and, prefixed `fate_`, its OpenCL kernel's name in launches(). fates/NAME.cpp includes fates/NAME.h inside
// namespace cellrules (cpu_physics.hpp), registers its field (if any) with Registrar<CellFieldInfo> and the rule.
struct FateRule {
  static constexpr const char* kKind = "fate rule";
  static constexpr const char* kListed = "fate-rules";
  int order = 60;  // its place among the effects (effect.hpp EffectInfo::order): after growth and division
  // The derived parameters (at most 64 doubles) from the scene's section; its errors name file, line and field.
  std::function<std::vector<double>(const Section&)> read;
  FateEvaluator decides = nullptr;
  std::string field;  // the per-cell field it keeps ("NAME.FIELD", effects/cell_fields.hpp), or "" for none
  // A valid section for it (YAML flow map): what the suites that iterate FateRules::names() run it with.
  std::string example = "{}";

  // Registering `name` (a C identifier) also registers the effect `name` (effect.hpp: a cell effect whose
  // after_cell_stage calls Backend::cell_fate). std::logic_error on a name that is not a C identifier.
  static void registering(const std::string& name, const FateRule& rule);
};
using FateRules = PluginKind<FateRule>;
// What the backend runs for the registered fate rule `rule` (its evaluator; `params` its derived parameters);
// std::logic_error for an unregistered rule.
FateCall fate_call(const std::string& rule, std::vector<double> params);

}  // namespace semlb::engine
