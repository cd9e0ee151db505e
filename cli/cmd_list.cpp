// `semlb list WHAT [--json]`: what the registries hold (policies, the policies a simulation can run, effects and
// the plug-in kinds among them, backends, cell types, runners, launchers, cell fields).
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "common/errors.hpp"
#include "controllers/policy.hpp"
#include "engine/backends/backend.hpp"
#include "engine/decomposition/decomposition.hpp"
#include "engine/effects/cell_fields.hpp"
#include "engine/division/division_rule.hpp"
#include "engine/effects/effect.hpp"
#include "engine/fates/fate.hpp"
#include "engine/growth/growth_law.hpp"
#include "engine/pairs/pair_term.hpp"
#include "engine/removal/removal.hpp"
#include "engine/terms/term.hpp"
#include "engine/model/state.hpp"
#include "experiments/runner.hpp"
#include "experiments/sweep.hpp"

namespace semlb::cli {
namespace {

// The policies the engine runs (engine::check_engine_policy accepts them: they need no true work of the next
// interval), in name order: what `semlb sim`, the MPI runners and `semlb replay --score` on engine traces take.
std::vector<std::string> engine_policies() {
  std::vector<std::string> out;
  for (const auto& n : policy_names()) {
    try {
      engine::check_engine_policy(n);
      out.push_back(n);
    } catch (const InputError&) {  // a surrogate baseline (oracle, foresight, ...)
    }
  }
  return out;
}

// Cell type names by type index: the order of the state files' /elements/type.
std::vector<std::string> cell_types() {
  std::vector<std::string> out;
  for (int t = 0; t < engine::kCellTypes; ++t) out.push_back(engine::type_name(t));
  return out;
}

// Every kind `semlb list` knows, in the order its help names them: its name and the function giving its names.
struct Kind {
  const char* name;
  std::vector<std::string> (*names)();
};
const Kind kKinds[] = {{"policies", policy_names},          {"engine-policies", engine_policies},
                       {"effects", engine::effect_names},    {"backends", engine::backend_names},
                       {"cell-types", cell_types},           {"runners", experiments::runner_names},
                       {"launchers", experiments::launcher_names}, {"cell-fields", engine::cell_field_names},
                       {"pair-terms", engine::pair_term_names},   {"element-terms", engine::element_term_names},
                       {"fate-rules", engine::fate_rule_names},   {"removal-rules", engine::removal_rule_names},
                       {"growth-laws", engine::growth_law_names}, {"division-rules", engine::division_rule_names}};

}  // namespace

std::vector<std::string> registered(const std::string& what) {
  for (const auto& k : kKinds)
    if (what == k.name) return k.names();
  throw std::logic_error("semlb list: no kind '" + what + "'");  // callers pass one of kKinds
}

std::string registered_list(const std::string& what) {
  std::string out;
  for (const auto& n : registered(what)) out += (out.empty() ? "" : ", ") + n;
  return out;
}

Action add_list(CLI::App& app) {
  struct Opts {
    std::string what;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  std::vector<std::string> kinds;
  for (const auto& k : kKinds) kinds.push_back(k.name);
  auto* sub = app.add_subcommand("list", "List what the registries hold, one name per line (or a JSON array)");
  sub->add_option("what", o->what,
                  "policies, engine-policies (those a simulation can run: no true work needed), effects, backends, "
                  "cell-types (by type index), runners, launchers, cell-fields (the per-cell fields effects declare), "
                  "the effects of one plug-in kind: pair-terms (a scene lists one), element-terms, fate-rules, removal-rules, "
                  "or the values of effects.growth.law (growth-laws) and effects.division.rule (division-rules)")
      ->required()
      ->check(CLI::IsMember(kinds));
  sub->add_flag("--json", o->json, "Print a JSON array of the names");
  return [o, sub] {
    if (!*sub) return -1;  // not the chosen subcommand
    const auto names = registered(o->what);
    if (o->json) {
      std::cout << nlohmann::json(names).dump() << "\n";
    } else {
      for (const auto& n : names) std::cout << n << "\n";
    }
    return 0;
  };
}

}  // namespace semlb::cli
