// The "workload_eval" runner: one policy replayed on one engine workload file at one rank count through the time
// model (surrogate/workload_replay.hpp): `semlb replay --workload`'s rollout as sweep rows.
#include <limits>
#include <map>
#include <memory>
#include <mutex>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "controllers/workload.hpp"
#include "runner.hpp"
#include "surrogate/workload_replay.hpp"

namespace semlb::experiments {
namespace {

bool is_model_key(const std::string& k) { return k.rfind("time_model.", 0) == 0; }

class WorkloadEvalRunner final : public Runner {
 public:
  // workload: the file as the manifest names it; events: intervals replayed; loop_s: the projected loop time (s);
  // ideal_s: the loop time of a perfect balance; the rest as the surrogate runner's.
  std::vector<std::string> columns() const override {
    return {"workload",
            "policy",
            "ranks",
            "seed",
            "events",
            "slices",
            "mean_imbalance",
            "migration",
            "loop_s",
            "ideal_s",
            "migrate_s",
            "first_quarter_imbalance",
            "last_quarter_imbalance",
            "us_per_decision"};
  }

  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    check_settings(
        job, manifest, {"policy", "ranks", "seed", "workload", "events", "first_event", "coarsen"},
        [](const std::string& k) { return is_model_key(k) || is_policy_param(k); }, "the workload_eval runner");
    const auto r = replay_of(job, manifest);
    const Setting* w = job.find("workload");
    if (!w) throw InputError(where(manifest, 0, "workload") + "missing (an engine workload file, output.workload)");
    std::shared_ptr<const EngineWorkload> workload;
    try {
      workload = load(o.resolve(w->value));
    } catch (const InputError& e) {
      throw InputError(where_of(*w, manifest, "workload") + e.what());
    }
    try {
      surrogate::replay_track(*workload, r, o.resolve(w->value));
    } catch (const InputError& e) {
      throw InputError(where_of(*job.find("ranks"), manifest, "ranks") + e.what());
    }
    check_policy_params(job, manifest);
    const Setting* p = job.find("policy");
    if (!p) throw InputError(where(manifest, 0, "policy") + "missing (the workload_eval runner needs it)");
    try {
      make_policy(p->value, policy_params(job, manifest)[p->value]);
    } catch (const InputError& e) {
      throw InputError(where_of(*p, manifest, "policy") + e.what());
    }
  }

  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& o) const override {
    const auto r = replay_of(job, "");
    const Setting& w = *job.find("workload");
    const std::string name = job.find("policy")->value;
    auto policy = make_policy(name, policy_params(job, "")[name]);
    const auto workload = load(o.resolve(w.value));
    const auto res = surrogate::replay_workload(*workload, r, *policy, name, o.resolve(w.value));
    return {{w.value, name, std::to_string(r.ranks), std::to_string(r.seed), std::to_string(res.events),
             std::to_string(res.slices), format_real(res.mean_imbalance), std::to_string(res.migration),
             format_real(res.loop_s), format_real(res.ideal_s), format_real(res.migrate_s),
             format_real(res.first_quarter_imbalance), format_real(res.last_quarter_imbalance),
             o.timing ? format_real(res.us_per_decision) : "0"}};
  }

 private:
  // Each workload file is read once per sweep (jobs share it; the sweep may run jobs on several threads).
  std::shared_ptr<const EngineWorkload> load(const std::string& path) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& slot = cache_[path];
    if (!slot) slot = std::make_shared<const EngineWorkload>(read_workload(path));
    return slot;
  }
  mutable std::mutex mutex_;
  mutable std::map<std::string, std::shared_ptr<const EngineWorkload>> cache_;

  static surrogate::WorkloadReplay replay_of(const Job& job, const std::string& manifest) {
    surrogate::WorkloadReplay r;
    if (!job.find("ranks"))
      throw InputError(where(manifest, 0, "ranks") + "missing (the workload_eval runner needs it)");
    r.ranks = static_cast<int>(job.integer("ranks", 0, 1, 1 << 20, manifest));
    r.seed = static_cast<uint64_t>(job.integer("seed", 0, 0, std::numeric_limits<long>::max(), manifest));
    r.events = static_cast<int>(job.integer("events", 0, 0, 1 << 30, manifest));
    r.first_event = static_cast<int>(job.integer("first_event", 0, 0, 1 << 30, manifest));
    r.coarsen = static_cast<int>(job.integer("coarsen", 1, 1, 1 << 20, manifest));
    for (const auto& [k, s] : job.settings)
      if (is_model_key(k)) surrogate::set_time_model(r.model, k.substr(11), s.value, where_of(s, manifest, k));
    return r;
  }
};

const Registrar<RunnerInfo> registrar("workload_eval", {[] { return std::make_unique<WorkloadEvalRunner>(); }});

}  // namespace
}  // namespace semlb::experiments
