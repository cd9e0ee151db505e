// `semlb surrogate`: controller evaluation on held-out scenarios -> DIR/controller_eval.csv.
#include <iostream>

#include "commands.hpp"
#include "result_table.hpp"
#include "common/text_io.hpp"
#include "common/version.hpp"
#include "experiments/sweep.hpp"
#include "surrogate/evaluate.hpp"

namespace semlb::cli {

Action add_surrogate(CLI::App& app) {
  struct Opts {
    std::string policies, ranks = "2,4,8,16", seeds = "9000-9019", out, weights;
    int events = 100, jobs = 1;
    std::vector<std::string> params, scenario;
    bool dump_traces = false, no_timing = false, quiet = false, resume = false;
  };
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("surrogate", "Evaluate policies on surrogate scenarios (hard integer boundaries)");
  sub->add_option("--policies", o->policies, "Comma-separated policy names: " + registered_list("policies"))
      ->required();
  sub->add_option("--ranks", o->ranks, "Rank counts, e.g. 2,4,8,16 or 2-16")->capture_default_str();
  sub->add_option("--seeds", o->seeds, "Scenario seeds, inclusive ranges (evaluation seeds: 9000-9999)")
      ->capture_default_str();
  sub->add_option("--events", o->events, "Rebalancing events per rollout")
      ->capture_default_str()
      ->check(strict_integer(1));
  sub->add_option("--out", o->out, "Output directory (writes DIR/controller_eval.csv)")->required();
  sub->add_option("--weights", o->weights, "GRU weights file (HDF5); default: the shipped weights");
  sub->add_option("--param", o->params, "Policy parameter POLICY.KEY=VALUE, e.g. reactive.tau=0.05 (repeatable)");
  sub->add_option(
      "--scenario", o->scenario,
      "Scenario override KEY=VALUE replacing the seed's draw, e.g. drift_speed=0.001 (repeatable; keys: docs/surrogate.md)");
  sub->add_option("--jobs", o->jobs, "Worker threads")->capture_default_str()->check(strict_integer(1));
  sub->add_flag("--dump-traces", o->dump_traces, "Also write every rollout as a JSON Lines trace under DIR/traces/");
  sub->add_flag("--no-timing", o->no_timing, "Write us_per_decision as 0 so that reruns are byte-identical");
  sub->add_flag("--quiet", o->quiet, "No progress line");
  sub->add_flag("--resume", o->resume, "Resume an interrupted run into the same DIR (default: start afresh)");
  return [o, sub] {
    if (!*sub) return -1;  // not the chosen subcommand
    experiments::Manifest m;
    m.name = "surrogate";
    m.runner = "surrogate";
    m.output = "controller_eval.csv";
    std::vector<experiments::Setting> policies, ranks, seeds;
    // Each value remembers its flag, so that errors name it ("--ranks: ranks = 2000 must be in ...").
    for (const auto& p : split(o->policies, ',')) policies.push_back({p, 0, "--policies"});
    for (long r : surrogate::parse_int_list(o->ranks, "--ranks")) ranks.push_back({std::to_string(r), 0, "--ranks"});
    for (long s : surrogate::parse_int_list(o->seeds, "--seeds")) seeds.push_back({std::to_string(s), 0, "--seeds"});
    m.axes = {{"policy", policies}, {"ranks", ranks}, {"seed", seeds}};
    m.fixed["events"] = {std::to_string(o->events), 0, "--events"};
    // One value per key: a second --param or --scenario of the same key (or --param gru.weights beside --weights)
    // is refused rather than silently replacing the first.
    const auto put = [&](const std::string& key, const std::string& value, const std::string& flag) {
      if (const auto it = m.fixed.find(key); it != m.fixed.end())
        throw InputError(flag + ": given twice (also " + it->second.source + ")");
      m.fixed[key] = {value, 0, flag};
    };
    if (!o->weights.empty()) put("gru.weights", o->weights, "--weights");
    for (const auto& p : o->params) {
      surrogate::parse_policy_params({p});  // validates the POLICY.KEY=VALUE shape
      put(p.substr(0, p.find('=')), p.substr(p.find('=') + 1), "--param " + p.substr(0, p.find('=')));
    }
    for (const auto& a : o->scenario) {
      const size_t eq = a.find('=');
      if (eq == std::string::npos || eq == 0) throw InputError("--scenario: '" + a + "' is not KEY=VALUE");
      put("scenario." + a.substr(0, eq), a.substr(eq + 1), "--scenario " + a.substr(0, eq));
    }
    experiments::SweepOptions so;
    so.results_dir = o->out;
    so.jobs = o->jobs;
    so.run.timing = !o->no_timing;
    so.run.trace_dir = o->dump_traces ? o->out + "/traces" : "";
    so.progress = !o->quiet;
    so.fresh = !o->resume;
    so.git_revision = version_string();
    so.command_line = command_line();
    const auto sum = experiments::run_sweep(m, {}, so);
    if (!o->quiet) std::cerr << result_table(sum.csv_path, {"policy", "ranks"});
    std::cerr << "wrote " << sum.csv_path << " (" << sum.rows << " rows)\n";
    return 0;
  };
}

}  // namespace semlb::cli
