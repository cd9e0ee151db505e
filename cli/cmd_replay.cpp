// `semlb replay`: apply a policy to a recorded trace, event after event, printing its decisions; with --score,
// run it on the trace's recorded work and print one JSON line of metrics (docs/controllers.md "Replay").
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "result_table.hpp"
#include "common/errors.hpp"
#include "controllers/partition.hpp"
#include "controllers/trace.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/rollout.hpp"
#include "surrogate/workload_replay.hpp"
#include "controllers/workload.hpp"

namespace semlb::cli {

Action add_replay(CLI::App& app) {
  struct Opts {
    std::string policy, weights, trace, workload;
    std::vector<std::string> params, model;
    bool score = false;
    int ranks = 0, first_event = 0, events = 0, coarsen = 1;
    long seed = 0;
  };
  auto o = std::make_shared<Opts>();
  auto* sub =
      app.add_subcommand("replay", "Apply a policy to a JSON Lines trace; prints one JSON line per event. Policies: " +
                                       registered_list("policies"));
  sub->add_option("--policy", o->policy, "Policy name")->required();
  auto* trace = sub->add_option("--trace", o->trace, "Trace file (JSON Lines, one event per line)");
  auto* workload =
      sub->add_option("--workload", o->workload,
                      "Engine workload file (HDF5, output.workload): replay at --ranks P through the time model; "
                      "prints one JSON line {ranks, events, mean_imbalance, migration, loop_s, ...}");
  trace->excludes(workload);
  sub->add_option("--ranks", o->ranks, "With --workload: the rank count P")->check(strict_integer(1, 1 << 20));
  sub->add_option("--seed", o->seed, "With --workload: seed of the time model's speed factors and jitter")
      ->check(strict_integer(0, 1L << 53));
  sub->add_option("--first-event", o->first_event, "With --workload: the first event replayed")
      ->check(strict_integer(0, 1 << 30));
  sub->add_option("--events", o->events, "With --workload: events replayed (0: to the end)")
      ->check(strict_integer(0, 1 << 30));
  sub->add_option("--coarsen", o->coarsen, "With --workload: adjacent slices merged into one")
      ->check(strict_integer(1, 1 << 20));
  std::string keys;
  for (const auto& k : surrogate::time_model_keys()) keys += (keys.empty() ? "" : ", ") + k;
  sub->add_option("--time-model", o->model, "With --workload: KEY=VALUE of the time model (" + keys + "; repeatable)");
  sub->add_option("--weights", o->weights, "GRU weights file (HDF5)");
  sub->add_option("--param", o->params, "Policy parameter POLICY.KEY=VALUE (repeatable)");
  sub->add_flag("--score", o->score,
                "Run the policy on the trace's slice_work as the true work, from its first boundaries; print one JSON "
                "line {events, mean_imbalance, migration, mean_max_over_mean}");
  return [o, sub] {
    if (!*sub) return -1;  // not the chosen subcommand
    auto params = surrogate::parse_policy_params(o->params);
    for (const auto& p : o->params)  // a parameter of another policy would be ignored
      if (p.rfind(o->policy + ".", 0) != 0)
        throw InputError("--param " + p.substr(0, p.find('=')) + ": the replayed policy is '" + o->policy + "'");
    if (!o->weights.empty()) params[o->policy].set("weights", o->weights);
    std::unique_ptr<Policy> policy;
    try {
      policy = make_policy(o->policy, params[o->policy]);
    } catch (const InputError& e) {  // name the --param a parameter's error is about, as `semlb surrogate` does
      const std::string what = e.what();
      for (const auto& p : o->params) {
        const size_t dot = p.find('.'), eq = p.find('=');
        if (what.find("parameter '" + p.substr(dot + 1, eq - dot - 1) + "'") != std::string::npos)
          throw InputError("--param " + p.substr(0, eq) + ": " + what);
      }
      throw;
    }
    if (o->trace.empty() == o->workload.empty()) throw InputError("replay: give --trace or --workload");
    if (!o->workload.empty() && o->score)
      throw InputError("replay: --score is for --trace (a --workload replay always prints its score)");
    if (!o->trace.empty())
      for (const char* flag : {"--ranks", "--seed", "--first-event", "--events", "--coarsen", "--time-model"})
        if (sub->count(flag)) throw InputError(std::string("replay: ") + flag + " is for --workload, not --trace");
    if (!o->workload.empty()) {
      if (o->ranks < 1) throw InputError("replay: --workload needs --ranks P");
      surrogate::WorkloadReplay r;
      r.ranks = o->ranks;
      r.seed = static_cast<uint64_t>(o->seed);
      r.first_event = o->first_event;
      r.events = o->events;
      r.coarsen = o->coarsen;
      for (const auto& kv : o->model) {
        const auto eq = kv.find('=');
        if (eq == std::string::npos) throw InputError("--time-model: expected KEY=VALUE, got '" + kv + "'");
        if (r.model.given.count(kv.substr(0, eq)))
          throw InputError("--time-model " + kv.substr(0, eq) + ": given twice");
        surrogate::set_time_model(r.model, kv.substr(0, eq), kv.substr(eq + 1), "--time-model ");
      }
      const auto w = read_workload(o->workload);
      const auto res = surrogate::replay_workload(w, r, *policy, o->policy, o->workload);
      const nlohmann::json out = {{"ranks", r.ranks},
                                  {"events", res.events},
                                  {"mean_imbalance", res.mean_imbalance},
                                  {"migration", res.migration},
                                  {"loop_s", res.loop_s},
                                  {"compute_s", res.compute_s},
                                  {"migrate_s", res.migrate_s},
                                  {"ideal_s", res.ideal_s},
                                  {"first_quarter_imbalance", res.first_quarter_imbalance},
                                  {"last_quarter_imbalance", res.last_quarter_imbalance},
                                  {"truth", res.measured ? "measured" : "work"}};
      std::cout << out.dump() << '\n' << std::flush;  // the JSON line first, then the table on stderr
      std::cerr << result_row(
          {{"policy", o->policy}, {"P", std::to_string(r.ranks)}, {"events", std::to_string(res.events)}},
          {{"imbalance %", 100.0 * res.mean_imbalance},
           {"migration", static_cast<double>(res.migration)},
           {"loop s", res.loop_s},
           {"ideal s", res.ideal_s},
           {"migrate s", res.migrate_s}});
      return 0;
    }
    std::vector<TraceEvent> events;  // read and validate the whole trace before printing anything
    std::vector<long> lines;
    TraceReader reader(o->trace);
    while (auto e = reader.next()) {
      events.push_back(std::move(*e));
      lines.push_back(reader.line());
    }
    if (o->score) {
      const auto r = surrogate::replay_rollout(events, lines, o->trace, *policy, o->policy);
      const nlohmann::json out = {{"events", r.events},
                                  {"mean_imbalance", r.mean_imbalance},
                                  {"migration", r.migration},
                                  {"mean_max_over_mean", r.mean_max_over_mean}};
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
