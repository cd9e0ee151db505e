// `semlb replay`: apply a policy to a recorded trace, event after event, printing its decisions; with --score,
// run it on the trace's recorded work and print one JSON line of metrics (docs/controllers.md "Replay").
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "common/errors.hpp"
#include "controllers/partition.hpp"
#include "controllers/trace.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/rollout.hpp"

namespace semlb::cli {

Action add_replay(CLI::App& app) {
  struct Opts {
    std::string policy, weights, trace;
    std::vector<std::string> params;
    bool score = false;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("replay", "Apply a policy to a JSON Lines trace; prints one JSON line per event. Policies: " +
                                            registered_list("policies"));
  sub->add_option("--policy", o->policy, "Policy name")->required();
  sub->add_option("--trace", o->trace, "Trace file (JSON Lines, one event per line)")->required();
  sub->add_option("--weights", o->weights, "GRU weights file (HDF5)");
  sub->add_option("--param", o->params, "Policy parameter POLICY.KEY=VALUE (repeatable)");
  sub->add_flag("--score", o->score,
                "Run the policy on the trace's slice_work as the true work, from its first boundaries; print one JSON "
                "line {events, mean_imbalance, migration, mean_max_over_mean}");
  return [o, sub] {
    if (!*sub) return -1;  // not the chosen subcommand
    auto params = surrogate::parse_policy_params(o->params);
    if (!o->weights.empty()) params[o->policy].set("weights", o->weights);
    auto policy = make_policy(o->policy, params[o->policy]);
    std::vector<TraceEvent> events;  // read and validate the whole trace before printing anything
    std::vector<long> lines;
    TraceReader reader(o->trace);
    while (auto e = reader.next()) {
      events.push_back(std::move(*e));
      lines.push_back(reader.line());
    }
    if (o->score) {
      const auto r = surrogate::replay_rollout(events, lines, o->trace, *policy, o->policy);
      const nlohmann::json out = {{"events", r.events}, {"mean_imbalance", r.mean_imbalance},
                                  {"migration", r.migration}, {"mean_max_over_mean", r.mean_max_over_mean}};
      std::cout << out.dump() << '\n';
      return 0;
    }
    std::string printed;  // every decision first: an error at a later line leaves no partial output
    for (size_t i = 0; i < events.size(); ++i) {
      const auto& e = events[i];
      std::vector<int> next;
      try {
        next = policy->decide(e.obs);
        check_partition(next, e.obs.slices, e.obs.min_width);
      } catch (const std::exception& err) {
        throw InputError(where(o->trace, lines[i], "") + "policy '" + o->policy + "': " + err.what());
      }
      nlohmann::json out = {{"event", e.obs.event}, {"boundaries", next}, {"moved", migration(e.obs.boundaries, next)}};
      printed += out.dump() + '\n';
    }
    std::cout << printed;
    return 0;
  };
}

}  // namespace semlb::cli
