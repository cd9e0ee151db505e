// Pair terms: the force between two elements within the cutoff (V_ele of the paper's eq. 1), each written once as
// a C99 evaluator header (pairs/NAME.h) and registered by name; the pair loops around it are written once per
// backend (serial, cpu-binned, and the OpenCL program built for the scene's term: pair_forces.cl, neighbour_list.cl).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "device/backend.hpp"
#include "model/scene.hpp"

namespace semlb::engine {

// A registered pair term. Its name is its scene key (`effects.NAME`) and the stem of its evaluator header
// pairs/NAME.h, whose `semlb_real semlb_pair_NAME(semlb_real r, int info_i, int info_j, SEMLB_CONST const
// semlb_real* p)` gives f(r) = -dV/dr (force units, positive repulsive) for 0 <= r < cutoff um, the same for
// (info_j, info_i) as for (info_i, info_j) (Newton's third law: opencl-binned's `newton` evaluates a pair once and
// gives j the negated force; test_pairs checks it for every registered term). pairs/NAME.cpp
// compiles it in both precisions (#define SEMLB_PAIR_HEADER "pairs/NAME.h" and SEMLB_PAIR_NAME NAME, then
// #include "pairs/instantiate.hpp") and registers phys64::NAME::pair and phys32::NAME::pair as f64 and f32.
struct PairTerm {
  static constexpr const char* kKind = "pair term";
  static constexpr const char* kListed = "pair-terms";
  int order = 10;  // its place among the effects (effect.hpp EffectInfo::order)
  // The derived parameters (reals, at most kMaxPluginParams) from the scene's section and the scene's cutoff (um);
  // the section's errors name file, line and field.
  std::function<std::vector<double>(const Section&, double cutoff)> read;
  PairEvaluator<double> f64 = nullptr;
  PairEvaluator<float> f32 = nullptr;
  // A valid section for it (YAML flow map): what the suites that iterate PairTerms::names() run it with.
  std::string example = "{}";

  // Registering `name` (a C identifier: the OpenCL program is built with -DSEMLB_PAIR_TERM=semlb_pair_NAME) also
  // registers the effect `name` that adds the pair forces (both parts: local and non-local). A scene lists one pair
  // term at most (InputError naming the second). std::logic_error on a name that is not a C identifier.
  static void registering(const std::string& name, const PairTerm& term);
};
using PairTerms = PluginKind<PairTerm>;
// What the backend runs for the registered pair term `term` (PairForces: its evaluators, `params` its derived
// parameters, `cutoff` um); std::logic_error for an unregistered term.
PairForces pair_forces_of(const std::string& term, std::vector<double> params, double cutoff);
// The pair term `scene` lists ("" when none): what the OpenCL backends build their program for
// (BackendConfig::pair_term).
std::string scene_pair_term(const Scene& scene);

}  // namespace semlb::engine
