// Runner registry.
#include "runner.hpp"

#include <map>

#include "common/errors.hpp"

namespace semlb::experiments {
namespace {
std::map<std::string, std::function<std::unique_ptr<Runner>()>>& registry() {
  static std::map<std::string, std::function<std::unique_ptr<Runner>()>> r;
  return r;
}
}  // namespace

std::vector<std::string> scene_overrides(const Job& job, const std::vector<std::pair<std::string, std::string>>& keys) {
  std::vector<std::string> o;
  for (const auto& [key, scene_key] : keys)
    if (const Setting* s = job.find(key)) o.push_back(scene_key + "=" + s->value);
  for (const auto& [k, s] : job.settings)
    if (k.rfind("scene.", 0) == 0) o.push_back(k.substr(6) + "=" + s.value);
  return o;
}

RunnerRegistrar::RunnerRegistrar(const std::string& name, std::function<std::unique_ptr<Runner>()> factory) {
  registry()[name] = std::move(factory);
}

std::unique_ptr<Runner> make_runner(const std::string& name, const std::string& manifest) {
  auto it = registry().find(name);
  if (it == registry().end()) {
    std::string known;
    for (const auto& [k, v] : registry()) known += (known.empty() ? "" : ", ") + k;
    throw InputError(where(manifest, 0, "runner") + "unknown runner '" + name + "' (known: " + known + ")");
  }
  return it->second();
}

}  // namespace semlb::experiments
