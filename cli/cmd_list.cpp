// `semlb list WHAT [--json]`: what the registries hold, every kind read from the catalogue of kinds
// (common/registry.hpp listed_kinds: each plug-in kind, the policies a simulation can run, the cell types);
// `semlb list kinds` names the kinds.
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "common/errors.hpp"
#include "common/registry.hpp"
#include "controllers/policy.hpp"
#include "engine/decomposition/decomposition.hpp"
#include "engine/model/state.hpp"

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

// The two lists that are no registry: in the catalogue of kinds beside the registries (common/registry.hpp).
const ListedKind engine_policies_kind("engine-policies", engine_policies);
const ListedKind cell_types_kind("cell-types", cell_types);

}  // namespace

std::vector<std::string> registered(const std::string& what) {
  if (what == "kinds") return listed_kinds().names();
  if (const KindNames* names = listed_kinds().find(what)) return (*names)();
  throw std::logic_error("semlb list: no kind '" + what + "'");  // callers pass one of listed_kinds()
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
  std::vector<std::string> kinds = listed_kinds().names();
  kinds.insert(kinds.begin(), "kinds");
  auto* sub = app.add_subcommand("list", "List what the registries hold, one name per line (or a JSON array)");
  sub->add_option(
         "what", o->what,
         "kinds (every kind this list knows), or one kind: " + listed_kinds().known() +
             ". engine-policies are the policies a simulation can run (no true work needed), cell-types are by "
             "type index, cell-fields the per-cell fields effects declare; pair-terms, element-terms, "
             "fate-rules and removal-rules are effects of one plug-in kind (a scene lists one pair term); "
             "growth-laws and division-rules are the values of effects.growth.law and effects.division.rule")
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
