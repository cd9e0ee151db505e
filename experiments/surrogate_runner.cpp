// The "surrogate" runner: one controller-evaluation rollout per job (keys: policy, ranks, seed, events,
// POLICY.KEY policy parameters such as holt.alpha, and scenario.KEY overrides of the scenario draws).
#include <limits>

#include "common/errors.hpp"
#include "runner.hpp"
#include "surrogate/evaluate.hpp"
#include "surrogate/scenario.hpp"

namespace semlb::experiments {
namespace {

const Setting& required(const Job& job, const std::string& key, const std::string& manifest) {
  const Setting* s = job.find(key);
  if (!s) throw InputError(where(manifest, 0, key) + "missing (the surrogate runner needs it)");
  return *s;
}

class SurrogateRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override { return surrogate::eval_columns(); }

  void check(const Job& job, const std::string& manifest, const RunOptions&) const override {
    const auto j = to_eval_job(job, manifest);
    check_settings(
        job, manifest, {"policy", "ranks", "seed", "events"},
        [](const std::string& k) { return is_scenario_key(k) || is_policy_param(k); }, "the surrogate runner");
    try {  // the scenario's slice count bounds the rank count: checked here, before any output exists
      surrogate::make_scenario(j.seed, j.ranks, j.scenario);
    } catch (const InputError& e) {
      const std::string m = e.what();
      for (const auto& [k, s] : job.settings)  // an override's error ("scenario.KEY: ...") names its setting
        if (is_scenario_key(k) && m.rfind(k + ": ", 0) == 0)
          throw InputError(where_of(s, manifest, k) + m.substr(k.size() + 2));
      throw InputError(where_of(*job.find("ranks"), manifest, "ranks") + m + " (scenario seed " +
                       std::to_string(j.seed) + ")");
    }
    check_policy_params(job, manifest);  // every policy's parameters, also of policies this row does not run
    try {
      make_policy(j.policy, policy_params(job, manifest)[j.policy]);
    } catch (const InputError& e) {
      const Setting* s = job.find("policy");
      throw InputError((s ? where_of(*s, manifest, "policy") : where(manifest, 0, "policy")) + e.what());
    }
  }

  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& options) const override {
    return {surrogate::run_eval_job(to_eval_job(job, ""), policy_params(job, ""), options.timing, options.trace_dir)};
  }

 private:
  static surrogate::EvalJob to_eval_job(const Job& job, const std::string& manifest) {
    surrogate::EvalJob j;
    j.policy = required(job, "policy", manifest).value;
    required(job, "ranks", manifest);
    required(job, "seed", manifest);
    j.ranks = static_cast<int>(job.integer("ranks", 0, 1, 1 << 20, manifest));
    j.seed = static_cast<uint64_t>(job.integer("seed", 0, 0, std::numeric_limits<long>::max(), manifest));
    j.events = static_cast<int>(job.integer("events", 100, 1, 1 << 30, manifest));
    for (const auto& [k, s] : job.settings)
      if (is_scenario_key(k)) j.scenario[k.substr(9)] = s.value;
    return j;
  }
};

const Registrar<RunnerInfo> registrar("surrogate", {[] { return std::make_unique<SurrogateRunner>(); }});

}  // namespace
}  // namespace semlb::experiments
