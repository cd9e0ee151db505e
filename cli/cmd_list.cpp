// `semlb list WHAT [--json]`: what the registries hold (policies, effects, backends, cell types, runners, launchers).
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "controllers/policy.hpp"
#include "engine/backends/backend.hpp"
#include "engine/effects/effect.hpp"
#include "engine/model/state.hpp"
#include "experiments/runner.hpp"
#include "experiments/sweep.hpp"

namespace semlb::cli {

std::vector<std::string> registered(const std::string& what) {
  if (what == "policies") return policy_names();
  if (what == "effects") return engine::effect_names();
  if (what == "backends") return engine::backend_names();
  if (what == "runners") return experiments::runner_names();
  if (what == "launchers") return experiments::launcher_names();
  std::vector<std::string> out;  // cell-types: by type index, the order of the state files' /elements/type
  for (int t = 0; t < engine::kCellTypes; ++t) out.push_back(engine::type_name(t));
  return out;
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
  auto* sub = app.add_subcommand("list", "List what the registries hold, one name per line (or a JSON array)");
  sub->add_option("what", o->what, "policies, effects, backends, cell-types (by type index), runners or launchers")
      ->required()
      ->check(CLI::IsMember({"policies", "effects", "backends", "cell-types", "runners", "launchers"}));
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
