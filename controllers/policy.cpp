// Policy registry and PolicyParams parsing.
#include "policy.hpp"

#include <algorithm>
#include <filesystem>

#include "common/errors.hpp"

namespace semlb {
namespace {

const PolicyInfo& entry(const std::string& name) {
  const PolicyInfo* e = PluginKind<PolicyInfo>::find(name);
  if (!e) throw InputError("unknown policy '" + name + "' (known: " + PluginKind<PolicyInfo>::known() + ")");
  return *e;
}

}  // namespace

void PolicyParams::set(const std::string& key, const std::string& value) {
  values_.set(key, value, Origin{"", 0, "policy parameter '" + key + "'", ""});
}

void PolicyParams::expect_all_used(const std::string& policy) const {
  const auto unread = values_.unread();
  if (!unread.empty())
    throw InputError("policy '" + policy + "' has no parameter '" + *std::min_element(unread.begin(), unread.end()) +
                     "'");
}

void Policy::load_state(const PolicyState& s) {
  if (!s.empty())
    throw InputError("policy state: this policy keeps no history, the checkpoint has '" + s.begin()->first + "'");
}

PolicyNeeds policy_needs(const std::string& name) { return entry(name).needs; }

std::unique_ptr<Policy> make_policy(const std::string& name, PolicyParams params) {
  auto policy = entry(name).factory(params);
  params.expect_all_used(name);
  return policy;
}

std::vector<std::string> policy_names() { return PluginKind<PolicyInfo>::names(); }

std::string resolve_weights_file(const std::string& path, const std::string& fallback) {
  if (path.empty()) return fallback;
  if (path.find('/') != std::string::npos || std::filesystem::exists(path)) return path;
  const auto shipped = std::filesystem::path(fallback).parent_path() / path;
  return std::filesystem::exists(shipped) ? shipped.string() : path;
}

}  // namespace semlb
