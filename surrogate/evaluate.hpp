// Controller evaluation grid: (policy x ranks x seed) rollouts -> controller_eval.csv rows.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "controllers/policy.hpp"
#include "scenario.hpp"

namespace semlb::surrogate {

struct EvalJob {
  std::string policy;
  int ranks = 2;
  uint64_t seed = 9000;
  int events = 100;
  ScenarioSet scenario;  // overrides of the seed's scenario draws (make_scenario)
};

// Column names and one row of controller_eval.csv (values already formatted; deterministic except
// us_per_decision, which is written as 0 when `timing` is false).
const std::vector<std::string>& eval_columns();
std::vector<std::string> run_eval_job(const EvalJob& job, const std::map<std::string, PolicyParams>& params,
                                      bool timing, const std::string& trace_dir = "");

// Inclusive integer lists like "9000-9019,9050" or "2,4,8,16"; errors name the flag.
std::vector<long> parse_int_list(const std::string& text, const std::string& flag);

// "gru.weights=F" style options -> per-policy parameters.
std::map<std::string, PolicyParams> parse_policy_params(const std::vector<std::string>& options);

}  // namespace semlb::surrogate
