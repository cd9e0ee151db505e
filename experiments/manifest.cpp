// Manifest loading (yaml-cpp) with line-accurate errors, profiles, overrides and axis expansion.
#include "manifest.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "common/yaml.hpp"
#include "surrogate/evaluate.hpp"

namespace semlb::experiments {
namespace {

long line_of(const YAML::Node& n) { return n.Mark().line + 1; }

std::string scalar(const YAML::Node& n, const std::string& file, const std::string& field) {
  if (!n.IsScalar()) throw InputError(where(file, line_of(n), field) + "must be a single value");
  return n.Scalar();
}

// An axis is a YAML list, or a scalar "A-B" / "a,b,c" (expanded like the CLI's --seeds).
std::vector<Setting> axis_values(const YAML::Node& n, const std::string& file, const std::string& field) {
  std::vector<Setting> out;
  if (n.IsSequence()) {
    for (const auto& v : n) out.push_back({scalar(v, file, field), line_of(v), ""});
  } else {
    const std::string text = scalar(n, file, field);
    if (text.find('-') != std::string::npos && text.find_first_not_of("0123456789-, ") == std::string::npos) {
      try {
        for (long v : surrogate::parse_int_list(text, field)) out.push_back({std::to_string(v), line_of(n), ""});
      } catch (const InputError& e) {
        throw InputError(where(file, line_of(n), field) + e.what());
      }
    } else {
      for (auto& v : split(text, ',')) out.push_back({std::move(v), line_of(n), ""});
    }
  }
  if (out.empty()) throw InputError(where(file, line_of(n), field) + "axis has no values");
  return out;
}

// Sets (or replaces) axis NAME in AXES.
void put_axis(Axes& axes, const std::string& name, std::vector<Setting> values) {
  auto it = std::find_if(axes.begin(), axes.end(), [&](auto& p) { return p.first == name; });
  if (it == axes.end())
    axes.emplace_back(name, std::move(values));
  else
    it->second = std::move(values);
}

Axes read_axes(const YAML::Node& n, const std::string& file, const std::string& field) {
  if (!n.IsMap() || n.size() == 0) throw InputError(where(file, line_of(n), field) + "must be a non-empty mapping");
  Axes axes;
  for (const auto& a : n) put_axis(axes, a.first.Scalar(), axis_values(a.second, file, field + "." + a.first.Scalar()));
  return axes;
}

// Removes axis NAME from AXES (no-op if absent).
void drop_axis(Axes& axes, const std::string& name) {
  axes.erase(std::remove_if(axes.begin(), axes.end(), [&](auto& p) { return p.first == name; }), axes.end());
}

// One block (the manifest's top level, or a profile): its axes replace earlier settings of the same key and its
// settings replace earlier axes (as --set does), but one block may not give a key both ways.
void read_block(const YAML::Node& block, Manifest& m, const std::string& where_name) {
  if (!block) return;
  if (!block.IsMap()) throw InputError(where(m.path, line_of(block), where_name) + "must be a mapping");
  std::map<std::string, int> block_axes;  // key -> line, of this block's axes (shared and groups)
  std::map<std::string, std::pair<int, std::string>> block_sets;  // key -> (line, field) of this block's settings
  for (const auto& kv : block) {
    if (kv.first.Scalar() == "axes" && kv.second.IsMap())
      for (const auto& a : kv.second) block_axes.emplace(a.first.Scalar(), line_of(a.first));
    if (kv.first.Scalar() == "groups" && kv.second.IsSequence())
      for (const auto& g : kv.second)
        if (g.IsMap())
          for (const auto& a : g) block_axes.emplace(a.first.Scalar(), line_of(a.first));
    if (kv.first.Scalar() == "set" && kv.second.IsMap())
      for (const auto& st : kv.second)
        block_sets.emplace(st.first.Scalar(), std::make_pair(line_of(st.first), "set." + st.first.Scalar()));
  }
  for (const auto& [key, at] : block_sets)
    if (const auto a = block_axes.find(key); a != block_axes.end())
      throw InputError(where(m.path, at.first, at.second) + "'" + key + "' is also an axis (line " +
                       std::to_string(a->second) + "): give it in one place");
  for (const auto& kv : block) {
    const std::string key = kv.first.Scalar();
    if (key == "axes") {
      if (!kv.second.IsMap()) throw InputError(where(m.path, line_of(kv.second), "axes") + "must be a mapping");
      for (const auto& a : kv.second) {
        const std::string name = a.first.Scalar();
        put_axis(m.axes, name, axis_values(a.second, m.path, "axes." + name));
        m.fixed.erase(name);
      }
    } else if (key == "groups") {  // a profile's groups replace the manifest's
      if (!kv.second.IsSequence() || kv.second.size() == 0)
        throw InputError(where(m.path, line_of(kv.second), "groups") + "must be a non-empty list of axis mappings");
      m.groups.clear();
      for (size_t i = 0; i < kv.second.size(); ++i) {
        m.groups.push_back(read_axes(kv.second[i], m.path, "groups[" + std::to_string(i) + "]"));
        for (const auto& a : m.groups.back()) m.fixed.erase(a.first);
      }
    } else if (key == "set") {
      if (!kv.second.IsMap()) throw InputError(where(m.path, line_of(kv.second), "set") + "must be a mapping");
      for (const auto& s : kv.second) {
        const std::string name = s.first.Scalar();
        m.fixed[name] = {scalar(s.second, m.path, "set." + name), line_of(s.second), ""};
        drop_axis(m.axes, name);  // a profile's setting replaces the manifest's axis
        for (auto& g : m.groups) drop_axis(g, name);
      }
    } else if (key == "launches") {
      m.launches_at = {scalar(kv.second, m.path, key), line_of(kv.second), ""};
      m.launches = parse_integer(m.launches_at.value, where(m.path, line_of(kv.second), key), 1, 1000);
    } else if (key == "output" || key == "runner" || key == "name") {
      const std::string v = scalar(kv.second, m.path, key);
      (key == "output" ? m.output : key == "runner" ? m.runner : m.name) = v;
    } else if (key != "profiles" && key != "description") {
      throw InputError(
          where(m.path, line_of(kv.first), key) +
          "unknown manifest key (known: name, description, runner, output, axes, groups, launches, set, profiles)");
    }
  }
}

}  // namespace

Origin origin_of(const Setting& s, const std::string& manifest) {
  return s.source.empty() ? Origin{manifest, s.line, "", ""} : Origin{"", 0, s.source, ""};
}

std::string where_of(const Setting& s, const std::string& manifest, const std::string& key) {
  return semlb::where(origin_of(s, manifest), key);
}

Settings Job::reader(const std::string& manifest) const {
  Settings r("", Origin{manifest, 0, "", ""});
  for (const auto& [k, s] : settings)
    if (!r.has(k)) r.set(k, s.value, origin_of(s, manifest));  // the first, as find() gives
  return r;
}

namespace {
// KEY of `job` alone as a semlb::Settings (a typed read of one key need not copy the row).
Settings one(const Job& job, const std::string& key, const std::string& manifest) {
  Settings r("", Origin{manifest, 0, "", ""});
  if (const Setting* s = job.find(key)) r.set(key, s->value, origin_of(*s, manifest));
  return r;
}
}  // namespace

long Job::integer(const std::string& key, long fallback, long min, long max, const std::string& manifest) const {
  return one(*this, key, manifest).integer(key, fallback, min, max);
}

double Job::real(const std::string& key, double fallback, double min, double max, const std::string& manifest) const {
  return one(*this, key, manifest).real(key, fallback, min, max);
}

const Setting* Job::find(const std::string& key) const {
  for (const auto& [k, v] : settings)
    if (k == key) return &v;
  return nullptr;
}

std::string Job::text(const std::string& key, const std::string& fallback) const {
  const Setting* s = find(key);
  return s ? s->value : fallback;
}

std::vector<std::string> Manifest::axis_names() const {
  std::vector<std::string> n;
  if (launches > 0) n.push_back("launch");
  for (const auto& a : axes) n.push_back(a.first);
  for (const auto& g : groups)
    for (const auto& a : g)
      if (std::find(n.begin(), n.end(), a.first) == n.end()) n.push_back(a.first);
  return n;
}

namespace {
std::vector<Job> product(const Axes& axes) {  // last axis fastest
  std::vector<Job> jobs(1);
  for (const auto& [name, values] : axes) {
    std::vector<Job> next;
    for (const auto& j : jobs)
      for (const auto& v : values) {
        Job k = j;
        k.settings.emplace_back(name, v);
        next.push_back(std::move(k));
      }
    jobs = std::move(next);
  }
  return jobs;
}
}  // namespace

std::vector<Job> Manifest::expand() const {
  std::vector<Job> jobs;
  if (groups.empty()) jobs = product(axes);
  for (const auto& g : groups) {
    Axes all = g;
    all.insert(all.end(), axes.begin(), axes.end());
    for (auto& j : product(all)) jobs.push_back(std::move(j));
  }
  for (auto& j : jobs)
    for (const auto& [k, v] : fixed) j.settings.emplace_back(k, v);
  if (launches == 0) return jobs;
  std::vector<Job> repeated;  // launch-major: launch 1 of every row, then launch 2, ...
  for (long l = 1; l <= launches; ++l)
    for (const auto& j : jobs) {
      Job k;
      k.settings.emplace_back("launch", Setting{std::to_string(l), launches_at.line, launches_at.source});
      k.settings.insert(k.settings.end(), j.settings.begin(), j.settings.end());
      repeated.push_back(std::move(k));
    }
  return repeated;
}

Manifest load_manifest(const std::string& path, const std::string& profile, const std::vector<std::string>& overrides) {
  const YAML::Node root = load_yaml_file(path, "manifest");
  Manifest m;
  m.path = path;
  if (!root.IsMap()) throw InputError(path + ": a manifest must be a YAML mapping");
  read_block(root, m, "");
  const auto profiles = root["profiles"];
  m.profile = profile.empty() && profiles && profiles["small"] ? "small" : profile;
  if (!m.profile.empty()) {
    if (!profiles || !profiles[m.profile])
      throw InputError(where(path, profiles ? line_of(profiles) : 0, "profiles") + "no profile '" + m.profile + "'");
    read_block(profiles[m.profile], m, "profiles." + m.profile);
  }
  for (const auto& o : overrides) {
    const size_t eq = o.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set: '" + o + "' is not KEY=VALUE");
    const std::string key = o.substr(0, eq);
    if (key == "launches") {
      m.launches_at = {o.substr(eq + 1), 0, "--set launches"};
      m.launches = parse_integer(m.launches_at.value, "--set launches: ", 1, 1000);
      continue;
    }
    bool axis = false;  // a shared axis, or the axis of every group that has it
    std::vector<Axes*> all{&m.axes};
    for (auto& g : m.groups) all.push_back(&g);
    for (Axes* axes : all) {
      auto it = std::find_if(axes->begin(), axes->end(), [&](auto& p) { return p.first == key; });
      if (it == axes->end()) continue;
      it->second = axis_values(YAML::Node(o.substr(eq + 1)), "--set", key);
      for (auto& v : it->second) v.source = "--set " + key;
      axis = true;
    }
    if (!axis) m.fixed[key] = {o.substr(eq + 1), 0, "--set " + key};
  }
  if (m.launches > 0) {  // `launch` is the sweep's own axis
    const bool taken = m.fixed.count("launch") ||
                       std::any_of(m.axes.begin(), m.axes.end(), [](auto& p) { return p.first == "launch"; }) ||
                       std::any_of(m.groups.begin(), m.groups.end(), [](const Axes& g) {
                         return std::any_of(g.begin(), g.end(), [](auto& p) { return p.first == "launch"; });
                       });
    if (taken)
      throw InputError(where_of(m.launches_at, path, "launches") +
                       "a manifest with launches may not set 'launch' itself");
  }
  for (size_t i = 0; i < m.groups.size(); ++i)
    for (const auto& [name, values] : m.groups[i])
      if (std::any_of(m.axes.begin(), m.axes.end(), [&](auto& p) { return p.first == name; }))
        throw InputError(where(path, values.front().line, "groups[" + std::to_string(i) + "]." + name) +
                         "is also a shared axis (under axes:); name it in one place");
  for (const auto& [field, value] : {std::pair{"name", &m.name}, {"runner", &m.runner}, {"output", &m.output}})
    if (value->empty()) throw InputError(where(path, 0, field) + "missing");
  return m;
}

}  // namespace semlb::experiments
