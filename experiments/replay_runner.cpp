// The "replay_score" runner: one policy (`semlb replay --score`'s rollout) on every engine trace.jsonl under a folder.
#include <algorithm>
#include <filesystem>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "controllers/trace.hpp"
#include "runner.hpp"
#include "surrogate/rollout.hpp"

namespace semlb::experiments {
namespace {

namespace fs = std::filesystem;

const char* const kTraceFile = "trace.jsonl";  // what the engine's rank 0 writes, kept by `sweep --keep-runs`

// The `traces` folder of a job: absolute, or relative to the manifest's folder; InputError naming its line when
// it is missing or not a folder.
fs::path traces_dir(const Job& job, const std::string& manifest, const RunOptions& o) {
  const Setting* s = job.find("traces");
  if (!s) throw InputError(where(manifest, 0, "traces") + "missing (the folder searched for " + kTraceFile + " files)");
  const fs::path p = o.resolve(s->value);
  if (!fs::is_directory(p)) throw InputError(where_of(*s, manifest, "traces") + "'" + p.string() + "' is not a folder");
  return p;
}

// Every file named trace.jsonl below `dir` (symbolic links to folders followed), sorted by path: the rows' order.
std::vector<fs::path> find_traces(const fs::path& dir) {
  std::vector<fs::path> found;
  for (const auto& e : fs::recursive_directory_iterator(dir, fs::directory_options::follow_directory_symlink))
    if (e.is_regular_file() && e.path().filename() == kTraceFile) found.push_back(e.path());
  std::sort(found.begin(), found.end());
  return found;
}

struct Trace {
  std::vector<TraceEvent> events;
  std::vector<long> lines;
};

Trace read_trace(const fs::path& path) {
  Trace t;
  TraceReader reader(path.string());
  while (auto e = reader.next()) {
    t.events.push_back(std::move(*e));
    t.lines.push_back(reader.line());
  }
  return t;
}

class ReplayScoreRunner final : public Runner {
 public:
  // trace: its folder relative to `traces` (e.g. load_balance/runs/initial=workload_policy=reactive); ranks and
  // slices: the trace's; the rest as `semlb replay --score` prints them.
  std::vector<std::string> columns() const override {
    return {"trace", "ranks", "slices", "events", "mean_imbalance", "migration", "mean_max_over_mean"};
  }

  // Refuses an unknown setting, a bad policy or POLICY.KEY, a missing `traces` folder, a folder without traces,
  // and any trace that does not parse or that --score refuses (FILE:LINE: field ...), before anything runs.
  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_settings(job, manifest, {"policy", "traces"}, is_policy_param, "the replay_score runner");
    const Setting* policy = job.find("policy");
    if (!policy) throw InputError(where(manifest, 0, "policy") + "missing (the replay_score runner needs it)");
    check_policy_params(job, manifest);
    try {
      make_policy(policy->value, policy_params(job, manifest)[policy->value]);
    } catch (const InputError& e) {
      throw InputError(where_of(*policy, manifest, "policy") + e.what());
    }
    const fs::path dir = traces_dir(job, manifest, o);
    const auto traces = find_traces(dir);
    if (traces.empty())
      throw InputError(where_of(*job.find("traces"), manifest, "traces") + "no " + kTraceFile + " under '" +
                       dir.string() + "' (engine runs keep theirs with `semlb sweep --keep-runs`)");
    for (const auto& path : traces) {  // parsed and checked as --score takes them (static: the cheapest rollout)
      const Trace t = read_trace(path);
      auto fixed = make_policy("static", {});
      surrogate::replay_rollout(t.events, t.lines, path.string(), *fixed, "static");
    }
  }

  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const std::string name = job.find("policy")->value;
    const fs::path dir = traces_dir(job, "", o);
    std::vector<std::vector<std::string>> rows;
    for (const auto& path : find_traces(dir)) {
      const Trace t = read_trace(path);
      auto policy = make_policy(name, policy_params(job, "")[name]);  // fresh state for every trace
      const auto r = surrogate::replay_rollout(t.events, t.lines, path.string(), *policy, name);
      const auto& first = t.events.front().obs;
      rows.push_back({fs::relative(path.parent_path(), dir).generic_string(), std::to_string(first.times.size()),
                      std::to_string(first.slices), std::to_string(r.events), format_real(r.mean_imbalance),
                      std::to_string(r.migration), format_real(r.mean_max_over_mean)});
    }
    return rows;
  }
};

const Registrar<RunnerInfo> registrar("replay_score", {[] { return std::make_unique<ReplayScoreRunner>(); }});

}  // namespace
}  // namespace semlb::experiments
