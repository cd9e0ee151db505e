// `semlb replay`: apply a policy to a recorded trace, event after event, printing its decisions.
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "controllers/partition.hpp"
#include "controllers/trace.hpp"
#include "surrogate/evaluate.hpp"

namespace semlb::cli {

Action add_replay(CLI::App& app) {
  struct Opts {
    std::string policy, weights, trace;
    std::vector<std::string> params;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("replay", "Apply a policy to a JSON Lines trace; prints one JSON line per event");
  sub->add_option("--policy", o->policy, "Policy name")->required();
  sub->add_option("--trace", o->trace, "Trace file (JSON Lines, one event per line)")->required();
  sub->add_option("--weights", o->weights, "GRU weights file (HDF5)");
  sub->add_option("--param", o->params, "Policy parameter POLICY.KEY=VALUE (repeatable)");
  return [o, sub] {
    if (!*sub) return -1;  // not the chosen subcommand
    auto params = surrogate::parse_policy_params(o->params);
    if (!o->weights.empty()) params[o->policy].set("weights", o->weights);
    auto policy = make_policy(o->policy, params[o->policy]);
    std::vector<TraceEvent> events;  // read and validate the whole trace before printing anything
    TraceReader reader(o->trace);
    while (auto e = reader.next()) events.push_back(std::move(*e));
    for (const auto& e : events) {
      const auto next = policy->decide(e.obs);
      nlohmann::json out = {{"event", e.obs.event}, {"boundaries", next}, {"moved", migration(e.obs.boundaries, next)}};
      std::cout << out.dump() << '\n';
    }
    return 0;
  };
}

}  // namespace semlb::cli
