// Policy registry and PolicyParams parsing.
#include "policy.hpp"

#include "errors.hpp"
#include "text_io.hpp"

namespace semlb {
namespace {

std::map<std::string, PolicyFactory>& registry() {
  static std::map<std::string, PolicyFactory> r;
  return r;
}

std::string joined_names() {
  std::string s;
  for (const auto& n : policy_names()) s += (s.empty() ? "" : ", ") + n;
  return s;
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

std::string PolicyParams::text(const std::string& key, const std::string& fallback) {
  used_.insert(key);
  auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

void PolicyParams::expect_all_used(const std::string& policy) const {
  for (const auto& [k, v] : values_)
    if (!used_.count(k)) throw InputError("policy '" + policy + "' has no parameter '" + k + "'");
}

Registrar::Registrar(const std::string& name, PolicyFactory factory) { registry()[name] = std::move(factory); }

std::unique_ptr<Policy> make_policy(const std::string& name, PolicyParams params) {
  auto it = registry().find(name);
  if (it == registry().end())
    throw InputError("unknown policy '" + name + "' (known: " + joined_names() + ")");
  auto policy = it->second(params);
  params.expect_all_used(name);
  return policy;
}

std::vector<std::string> policy_names() {
  std::vector<std::string> names;
  for (const auto& [k, v] : registry()) names.push_back(k);
  return names;
}

}  // namespace semlb
