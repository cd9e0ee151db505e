// The "surrogate" runner: one controller-evaluation rollout per job (keys: policy, ranks, seed, events,
// and POLICY.KEY policy parameters such as holt.alpha).
#include <charconv>

#include "controllers/errors.hpp"
#include "runner.hpp"
#include "surrogate/evaluate.hpp"

namespace semlb::experiments {
namespace {

long integer(const Job& job, const std::string& key, long fallback, bool required, const std::string& manifest) {
  const Setting* s = job.find(key);
  if (!s) {
    if (required) throw InputError(where(manifest, 0, key) + "missing (the surrogate runner needs it)");
    return fallback;
  }
  long v = 0;
  auto [p, ec] = std::from_chars(s->value.data(), s->value.data() + s->value.size(), v);
  if (ec != std::errc() || p != s->value.data() + s->value.size() || v < 0)
    throw InputError(where(manifest, s->line, key) + "'" + s->value + "' is not a non-negative integer");
  return v;
}

class SurrogateRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override { return surrogate::eval_columns(); }

  void check(const Job& job, const std::string& manifest, const RunOptions&) const override {
    const auto j = to_eval_job(job, manifest);
    for (const auto& [k, s] : job.settings)
      if (k != "policy" && k != "ranks" && k != "seed" && k != "events" && k.find('.') == std::string::npos)
        throw InputError(where(manifest, s.line, k) + "unknown setting for the surrogate runner");
    try {
      make_policy(j.policy, params(job)[j.policy]);
    } catch (const InputError& e) {
      const Setting* s = job.find("policy");
      throw InputError(where(manifest, s ? s->line : 0, "policy") + e.what());
    }
    for (const auto& [policy, p] : params(job)) {  // parameters of policies this row does not run are checked too
      try {
        make_policy(policy, p);
      } catch (const InputError& e) {
        const Setting* s = nullptr;
        for (const auto& [k, v] : job.settings)
          if (k.rfind(policy + ".", 0) == 0) s = &v;
        throw InputError(where(manifest, s ? s->line : 0, policy + ".*") + e.what());
      }
    }
  }

  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& options) const override {
    return {surrogate::run_eval_job(to_eval_job(job, ""), params(job), options.timing, options.trace_dir)};
  }

 private:
  static surrogate::EvalJob to_eval_job(const Job& job, const std::string& manifest) {
    surrogate::EvalJob j;
    const Setting* p = job.find("policy");
    if (!p) throw InputError(where(manifest, 0, "policy") + "missing (the surrogate runner needs it)");
    j.policy = p->value;
    j.ranks = static_cast<int>(integer(job, "ranks", 0, true, manifest));
    j.seed = static_cast<uint64_t>(integer(job, "seed", 0, true, manifest));
    j.events = static_cast<int>(integer(job, "events", 100, false, manifest));
    if (j.ranks < 1 || j.events < 1) throw InputError(where(manifest, job.find("ranks")->line, "ranks") + "ranks and events must be >= 1");
    return j;
  }

  static std::map<std::string, PolicyParams> params(const Job& job) {
    std::vector<std::string> options;
    for (const auto& [k, s] : job.settings)
      if (k.find('.') != std::string::npos) options.push_back(k + "=" + s.value);
    return surrogate::parse_policy_params(options);
  }
};

const RunnerRegistrar registrar("surrogate", [] { return std::make_unique<SurrogateRunner>(); });

}  // namespace
}  // namespace semlb::experiments
