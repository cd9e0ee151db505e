// Policy registry and PolicyParams parsing.
#include "policy.hpp"

#include "common/errors.hpp"
#include "common/registry.hpp"
#include "common/text_io.hpp"

namespace semlb {
namespace {

struct Entry {
  PolicyFactory factory;
  PolicyNeeds needs;
};

Registry<Entry>& registry() {
  static Registry<Entry> r;
  return r;
}

const Entry& entry(const std::string& name) {
  const Entry* e = registry().find(name);
  if (!e) throw InputError("unknown policy '" + name + "' (known: " + registry().known() + ")");
  return *e;
}

}  // namespace

double PolicyParams::real(const std::string& key, double fallback, double min, double max, bool min_open, bool max_open) {
  used_.insert(key);
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const std::string at = "policy parameter '" + key + "': ";
  const double v = parse_real(it->second, at);
  if (v < min || v > max || (min_open && v == min) || (max_open && v == max))
    throw InputError(at + "'" + it->second + "' is outside " + (min_open ? "(" : "[") + format_real(min) + ", " +
                     format_real(max) + (max_open ? ")" : "]"));
  return v;
}

long PolicyParams::integer(const std::string& key, long fallback, long min, long max) {
  used_.insert(key);
  auto it = values_.find(key);
  return it == values_.end() ? fallback : parse_integer(it->second, "policy parameter '" + key + "': ", min, max);
}

std::string PolicyParams::text(const std::string& key, const std::string& fallback) {
  used_.insert(key);
  auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

void PolicyParams::expect_all_used(const std::string& policy) const {
  for (const auto& [k, v] : values_)
    if (!used_.count(k)) throw InputError("policy '" + policy + "' has no parameter '" + k + "'");
}

void Policy::load_state(const PolicyState& s) {
  if (!s.empty()) throw InputError("policy state: this policy keeps no history, the checkpoint has '" + s.begin()->first + "'");
}

Registrar::Registrar(const std::string& name, PolicyFactory factory, PolicyNeeds needs) {
  registry().add(name, {std::move(factory), needs});
}

PolicyNeeds policy_needs(const std::string& name) { return entry(name).needs; }

std::unique_ptr<Policy> make_policy(const std::string& name, PolicyParams params) {
  auto policy = entry(name).factory(params);
  params.expect_all_used(name);
  return policy;
}

std::vector<std::string> policy_names() { return registry().names(); }

}  // namespace semlb
