// Policy interface and the by-name registry: a new policy is one .cpp with a Registrar, no core edit.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "common/settings.hpp"
#include "observation.hpp"

namespace semlb {

// A policy's history as named real arrays (e.g. "level", "trend", "hidden"), saved in checkpoints.
using PolicyState = std::map<std::string, std::vector<double>>;

// A rebalancing policy. It keeps its own history (Holt state, GRU hidden states) between events.
class Policy {
 public:
  virtual ~Policy() = default;
  // Returns the interior boundaries for the next interval. obs must be valid (see validate()).
  virtual std::vector<int> decide(const Observation& obs) = 0;
  // The history decide() depends on; empty for memoryless policies. load_state(save_state()) continues
  // identically. load_state throws InputError for a state of the wrong shape.
  virtual PolicyState save_state() const { return {}; }
  virtual void load_state(const PolicyState& s);
};

// What a policy reads besides times and boundaries; a run whose source cannot provide it is refused.
struct PolicyNeeds {
  bool slice_work = false;  // a per-slice workload estimate (Observation::slice_work)
  bool true_work = false;   // the noise-free work of the next interval (Observation::oracle_work)
};

// Largest imbalance threshold (tau) a policy accepts: I_t <= 2 and I_global <= P, so tau above this means
// "never rebalance" for any run semlb can make (ranges: docs/controllers.md "Input rules").
inline constexpr double kMaxThreshold = 100.0;

// key=value options of one policy (e.g. tau=0.02), read through semlb::Settings (common/settings.hpp): each value
// is blamed on "policy parameter 'KEY': ". Reading a key marks it used; unused keys are errors.
class PolicyParams {
 public:
  PolicyParams() = default;
  explicit PolicyParams(const std::map<std::string, std::string>& values) {
    for (const auto& [k, v] : values) set(k, v);
  }

  // KEY's value parsed strictly (parse_real), in [min, max] (an open end when min_open / max_open);
  // FALLBACK when absent. Throws InputError "policy parameter 'KEY': ...".
  double real(const std::string& key, double fallback, double min, double max, bool min_open = false,
              bool max_open = false) {
    return values_.real(key, fallback, min, max, min_open, max_open);
  }
  // KEY's value parsed strictly as an integer (parse_integer: "2.0" is refused), in [min, max]; FALLBACK when
  // absent. Throws InputError "policy parameter 'KEY': ...".
  long integer(const std::string& key, long fallback, long min, long max) {
    return values_.integer(key, fallback, min, max);
  }
  std::string text(const std::string& key, const std::string& fallback) { return values_.text(key, fallback); }
  void set(const std::string& key, const std::string& value);
  bool has(const std::string& key) const { return values_.has(key); }
  // Throws InputError "policy 'POLICY' has no parameter 'KEY'" for the first key (in name order) no policy code read.
  void expect_all_used(const std::string& policy) const;

 private:
  Settings values_;
};

// The file a policy's `weights` parameter names: empty -> `fallback` (the shipped default); a bare file name that does
// not exist here -> that name in the folder of `fallback` if it is there; anything else as given (its loader reports
// a missing file).
std::string resolve_weights_file(const std::string& path, const std::string& fallback);

using PolicyFactory = std::function<std::unique_ptr<Policy>(PolicyParams&)>;

// A registered policy: `const Registrar<PolicyInfo> registrar("name", {factory, needs});` (common/registry.hpp).
struct PolicyInfo {
  static constexpr const char* kKind = "policy";
  static constexpr const char* kListed = "policies";
  PolicyFactory factory;
  PolicyNeeds needs = {};
};

// Builds a registered policy; throws InputError for an unknown name or an unknown/invalid parameter.
std::unique_ptr<Policy> make_policy(const std::string& name, PolicyParams params = {});
std::vector<std::string> policy_names();
// What the named policy needs; InputError for an unknown name.
PolicyNeeds policy_needs(const std::string& name);

}  // namespace semlb
