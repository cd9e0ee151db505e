// Element terms: an external force on every owned element from its own position and cell type (V_ext of the
// paper's eq. 1), each written once as a C99 evaluator header (terms/NAME.h) and registered by name; the loop
// around it is written once per backend kind (CpuBackend::element_term, the OpenCL kernel template element_term.cl).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "physics/cpu_physics.hpp"
#include "common/registry.hpp"
#include "device/backend.hpp"
#include "model/scene.hpp"
#include "model/state.hpp"

namespace semlb::engine {

// A registered element term. Its name is its scene key (`effects.NAME`), the stem of its evaluator header
// terms/NAME.h (whose `semlb_term_NAME` the OpenCL kernel NAME calls) and its kernel's name in launches().
// terms/NAME.cpp compiles terms/NAME.h in both precisions (#define SEMLB_TERM_HEADER "terms/NAME.h", then
// #include "terms/instantiate.hpp") and registers phys64::semlb_term_NAME and phys32::semlb_term_NAME as f64 and f32.
struct ElementTerm {
  static constexpr const char* kKind = "element term";
  static constexpr const char* kListed = "element-terms";
  int order = 20;  // its place among the effects (effect.hpp EffectInfo::order)
  // The derived parameters (reals) from the scene's section; the section's errors name file, line and field.
  std::function<std::vector<double>(const Section&)> read;
  TermEvaluator<double> f64 = nullptr;
  TermEvaluator<float> f32 = nullptr;
  // A valid section for it (YAML flow map): what the suites that iterate ElementTerms::names() run it with.
  std::string example = "{}";
  // Optional: what is wrong with the initial state under these parameters (empty: nothing), e.g. elements behind a
  // wall; the effect then refuses the state with InputError naming the section.
  std::function<std::string(const State&, const std::vector<double>&)> check;

  // Registering `name` (a C identifier: it names the OpenCL kernel) also registers the effect `name` (effect.hpp:
  // adds_forces, the local part). std::logic_error on a name that is not a C identifier.
  static void registering(const std::string& name, const ElementTerm& term);
};
using ElementTerms = PluginKind<ElementTerm>;
// What the backend runs for the registered element term `name` (its evaluators; `params` its derived parameters);
// std::logic_error for an unregistered name.
ElementTermCall element_term_call(const std::string& name, std::vector<double> params);

}  // namespace semlb::engine
