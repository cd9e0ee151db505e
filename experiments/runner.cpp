// Runner registry.
#include "runner.hpp"

#include <algorithm>
#include <filesystem>
#include <map>

#include "common/errors.hpp"
#include "engine/model/scene.hpp"
#include "engine/run/driver.hpp"
#include "surrogate/evaluate.hpp"

namespace semlb::experiments {

std::string resolve_path(const std::string& base_dir, const std::string& file) {
  const std::filesystem::path p(file);
  return p.is_absolute() || base_dir.empty() ? file : (std::filesystem::path(base_dir) / p).string();
}

std::string RunOptions::resolve(const std::string& file) const { return resolve_path(base_dir, file); }

std::vector<std::string> scene_overrides(const Job& job, const std::vector<std::string>& names,
                                         const std::string& manifest, std::vector<std::string>* flags) {
  std::vector<std::string> o;
  const auto label = [&](const Setting& s, const std::string& key) {  // "m.yaml:7: field 'scene.x'", "--set scene.x"
    if (!flags) return;
    std::string w = where_of(s, manifest, key);
    flags->push_back(w.substr(0, w.size() - 2));  // without the ": " that ends a where
  };
  std::map<std::string, std::string> named;  // scene key -> the job's setting that sets it
  for (const auto& name : names)
    if (const Setting* s = job.find(name)) {
      o.push_back(engine::scene_override(name, s->value, where_of(*s, manifest, name)));
      label(*s, name);
      named[engine::scene_setting(name).key] = name;
    }
  for (const auto& [k, s] : job.settings)
    if (k.rfind("scene.", 0) == 0) {
      // the later override would win in silence, and the CSV's column would still show the named setting's value
      if (auto it = named.find(k.substr(6)); it != named.end())
        throw InputError(where_of(s, manifest, k) + "sets " + it->first + ", which the job's '" + it->second +
                         "' sets too; give it once (as '" + it->second + "')");
      o.push_back(k.substr(6) + "=" + s.value);
      label(s, k);
    }
  return o;
}

engine::Scene job_scene(const Job& job, const std::vector<std::string>& names, const std::string& manifest,
                        const std::string& base_dir) {
  const Setting* file = job.find("scene");
  if (!file) throw InputError(where(manifest, 0, "scene") + "missing (engine runners need a scene file)");
  std::vector<std::string> flags;  // where each override was set, named by the scene's errors about it
  const auto overrides = scene_overrides(job, names, manifest, &flags);  // its errors name their own settings
  try {
    engine::Scene scene = engine::load_scene(resolve_path(base_dir, file->value), overrides, flags);
    engine::check_scene(scene);  // every setting a run reads, checked before anything runs
    return scene;
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const auto& f : flags)  // an error about an override names its setting already
      if (what.rfind(f + ":", 0) == 0) throw;
    throw InputError(where_of(*file, manifest, "scene") + what);
  }
}

std::string job_key(const Job& job) {
  std::string key;
  for (const auto& [k, s] : job.settings) key += k + "=" + s.value + ";";
  return key;
}

void check_settings(const Job& job, const std::string& manifest, const std::vector<std::string>& known,
                    const std::function<bool(const std::string&)>& also, const std::string& runner) {
  const Settings row = job.reader(manifest);
  for (const auto& k : row.keys())
    if (std::find(known.begin(), known.end(), k) != known.end() || (also && also(k))) row.mark_read(k);
  row.finish("unknown setting for " + runner);
}

bool is_scenario_key(const std::string& key) { return key.rfind("scenario.", 0) == 0; }

bool is_policy_param(const std::string& key) {
  return key.find('.') != std::string::npos && key.rfind("scene.", 0) != 0 && key.rfind("time_model.", 0) != 0 &&
         !is_scenario_key(key);
}

std::map<std::string, PolicyParams> policy_params(const Job& job, const std::string& manifest) {
  std::vector<std::string> options;
  for (const auto& [k, s] : job.settings)
    if (is_policy_param(k)) {
      try {
        surrogate::parse_policy_params({k + "=" + s.value});
      } catch (const InputError&) {
        throw InputError(where_of(s, manifest, k) + "is not POLICY.KEY (a policy parameter such as holt.alpha)");
      }
      options.push_back(k + "=" + s.value);
    }
  return surrogate::parse_policy_params(options);
}

void check_policy_params(const Job& job, const std::string& manifest) {
  for (const auto& [policy, p] : policy_params(job, manifest)) {
    try {
      make_policy(policy, p);
    } catch (const InputError& e) {  // blame the parameter the message names (else the policy's first one)
      const Setting* s = nullptr;
      for (const auto& [k, v] : job.settings)
        if (k.rfind(policy + ".", 0) == 0 &&
            (!s || std::string(e.what()).find("'" + k.substr(policy.size() + 1) + "'") != std::string::npos))
          s = &v;
      throw InputError((s ? where_of(*s, manifest, policy + ".*") : where(manifest, 0, policy + ".*")) + e.what());
    }
  }
}

std::unique_ptr<Runner> make_runner(const std::string& name, const std::string& manifest) {
  const RunnerInfo* info = Runners::find(name);
  if (!info)
    throw InputError(where(manifest, 0, "runner") + "unknown runner '" + name + "' (known: " + Runners::known() + ")");
  return info->make();
}

}  // namespace semlb::experiments
