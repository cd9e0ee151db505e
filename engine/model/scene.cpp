// Scene parsing: overrides on the YAML tree, then checked sections with line-accurate errors.
#include "scene.hpp"

#include <climits>

#include <set>
#include <stdexcept>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "common/yaml.hpp"

namespace semlb::engine {

namespace {

// Where FIELD's value N came from: the --set that gave it, or a map holding it, or made the map on its way; else N's
// line of FILE.
Origin origin_of(const std::string& field, const YAML::Node& n, const std::string& file, const Overridden* overridden) {
  if (overridden) {      // a key set by --set, or inside a map given by --set (effects.noise={...}), is blamed on it:
    std::string prefix;  // the longest such path (a key a later --set gave inside a map an earlier one made)
    const Origin* found = nullptr;
    for (const auto& part : split(field, '.')) {
      prefix += (prefix.empty() ? "" : ".") + part;
      if (const auto it = overridden->find(prefix); it != overridden->end()) found = &it->second;
    }
    if (found) return *found;
  }
  return {file, n.IsDefined() ? n.Mark().line + 1 : 0, "", ""};
}

}  // namespace

Section::Section(YAML::Node node, std::string path, std::string file, std::shared_ptr<const Overridden> overridden)
    : Settings(path, origin_of(path, node.IsDefined() && !node.IsNull() ? node : YAML::Node(), file, overridden.get())),
      node_(std::move(node)),
      file_(std::move(file)),
      overridden_(std::move(overridden)) {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    Value v;
    v.origin = origin_of(field(key), kv.second, file_, overridden_.get());
    if (kv.second.IsScalar()) {
      v.text = kv.second.Scalar();
    } else if (kv.second.IsSequence()) {
      v.kind = Kind::list;
      for (const auto& item : kv.second) {
        if (!item.IsScalar() && !item.IsNull())
          v.kind = Kind::map;  // texts(): "must be a list" (of single values)
        else
          v.items.push_back(item.as<std::string>());
      }
    } else {
      v.kind = kv.second.IsMap() ? Kind::map : Kind::none;
    }
    set(key, std::move(v));
  }
}

Section Section::child(const std::string& key) const {
  mark_read(key);
  const YAML::Node& map = node_;  // const access: a missing key must not be inserted
  YAML::Node n = has(key) ? map[key] : YAML::Node(YAML::NodeType::Map);
  if (!n.IsMap() && !n.IsNull()) fail(key, "must be a map of settings");
  return Section(n.IsNull() ? YAML::Node(YAML::NodeType::Map) : n, field(key), file_, overridden_);
}

namespace {

// Refuses a flag's override of PATH that an earlier --set gave (its key, or a map holding PATH's key, or a value that
// replaced a map on PATH's way): the flag would hide that --set's value unread. SET: the paths the --sets gave.
void refuse_given_twice(const YAML::Node& root, const std::string& path, const std::string& flag,
                        const std::set<std::string>& set) {
  const auto parts = split(path, '.');
  std::string at, giver;  // the path so far; the --set at or above it
  YAML::Node node = root;
  for (size_t i = 0; i < parts.size(); ++i) {
    at += (i ? "." : "") + parts[i];
    if (set.count(at)) giver = at;
    const YAML::Node& here = node;                 // const: a missing key is not inserted
    if (!here.IsMap() || !here[parts[i]]) return;  // PATH's key is not in the tree: nothing hidden
    node.reset(here[parts[i]]);                    // rebinds (operator= would overwrite the node)
    if (!giver.empty() && (i + 1 == parts.size() || !node.IsMap()))
      throw InputError(flag + ": " + path + " is also given by --set " + giver + "; give it once");
  }
}

// Applies `a.b.c=value` to the tree, creating maps on the way; records the dotted path, and each map it made on the
// way, as given by FLAG (empty: "--set a.b.c", and the path goes into SET), the name its errors carry. A flag's
// override of what a --set before it gave is refused (refuse_given_twice).
void apply_override(YAML::Node root, const std::string& assignment, std::string flag, Overridden& overridden,
                    std::set<std::string>& set) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--set " + assignment + ": expected KEY=VALUE");
  const std::string path = assignment.substr(0, eq);
  if (flag.empty()) {
    flag = "--set " + path;
    set.insert(path);
  } else {
    refuse_given_twice(root, path, flag, set);
  }
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw InputError(flag + ": value is not YAML: " + e.msg);
  }
  refuse_duplicate_keys(value, flag);
  std::vector<YAML::Node> chain{root};
  const auto parts = split(path, '.');
  for (const auto& part : parts)
    if (part.empty()) throw InputError(flag + ": an empty key in the path (KEY.KEY=VALUE)");
  std::string made;  // the dotted path so far
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    made += (i ? "." : "") + parts[i];
    YAML::Node next = chain.back()[parts[i]];
    if (!next || next.IsNull()) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      overridden.emplace(made, Origin{"", 0, flag, path});  // a key the file lacks: its errors name this flag
    } else if (!next.IsMap()) {
      throw InputError(flag + ": '" + parts[i] + "' is not a map");
    }
    chain.push_back(chain.back()[parts[i]]);
  }
  chain.back()[parts.back()] = value;
  overridden[path] = Origin{"", 0, flag, path};
}

// The keys every backend has; the rest of the map is the chosen backend's (backends/backend.hpp backend_settings).
void read_backend(const Section& s, BackendConfig& b) {
  b.name = s.text("name", b.name);
  b.precision = s.text("precision", b.precision);
  if (b.precision != "double" && b.precision != "float") s.fail("precision", "must be double or float");
  b.settings = std::make_shared<const Section>(s);
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides,
                  const std::vector<std::string>& flags) {
  YAML::Node root = load_yaml(text, file, "scene");
  if (!root.IsMap()) throw InputError(file + ": a scene is a YAML map");
  auto overridden = std::make_shared<Overridden>();
  std::set<std::string> set;  // the paths the --sets gave
  for (size_t i = 0; i < overrides.size(); ++i)
    apply_override(root, overrides[i], i < flags.size() ? flags[i] : "", *overridden, set);
  const Section top(root, "", file, overridden);

  Scene s;
  s.path = file;
  s.text = YAML::Dump(root) + "\n";
  s.name = top.text("name", "scene");
  s.seed = static_cast<uint64_t>(top.integer("seed", 1, 0, (1L << 53)));
  s.cutoff = top.real("cutoff", s.cutoff, 1e-6, 1e6);
  const Section domain = top.child("domain");
  const auto lo = domain.texts("lo", {"auto"}), hi = domain.texts("hi", {"auto"});
  s.auto_box = lo.size() == 1 && hi.size() == 1 && lo[0] == "auto" && hi[0] == "auto";
  if (!s.auto_box) {
    if (lo.size() != 3 || hi.size() != 3) domain.fail("lo", "lo and hi are [x, y, z] in um, or both auto");
    for (int d = 0; d < 3; ++d) {  // um; every coordinate a whole finite number
      s.box_lo[d] = parse_real(lo[d], domain.where("lo"), -1e9, 1e9);
      s.box_hi[d] = parse_real(hi[d], domain.where("hi"), -1e9, 1e9);
      if (!(s.box_hi[d] > s.box_lo[d])) domain.fail("hi", "hi must exceed lo on every axis");
    }
  }
  domain.finish();
  const Section time = top.child("time");
  s.dt = time.real("dt", s.dt, 1e-12, 1e6);
  s.steps = time.integer("steps", s.steps, 0, INT_MAX);  // the device kernels count steps in 32 bits
  s.friction = time.real("friction", s.friction, 1e-12, 1e12);
  s.max_displacement = time.real("max_displacement", s.max_displacement, 1e-12, 1e12);
  s.cell_update_every = time.integer("cell_update_every", s.cell_update_every, 1, 1L << 30);
  time.finish();
  const Section output = top.child("output");
  s.snapshot_every = output.integer("snapshot_every", 0, 0, 1L << 40);
  s.log_every = output.integer("log_every", 100, 1, 1L << 40);
  s.checkpoint_every = output.integer("checkpoint_every", 0, 0, 1L << 40);
  s.record_workload = output.boolean("workload", false);
  s.write_final = output.boolean("final", true);
  output.finish();
  read_backend(top.child("backend"), s.backend);
  s.tissue = std::make_shared<Section>(top.child("tissue"));
  s.decomposition = std::make_shared<Section>(top.child("decomposition"));
  const Section effects = top.child("effects");
  for (const auto& name : effects.keys()) s.effects.emplace_back(name, effects.child(name));
  top.finish();
  return s;
}

const std::vector<SceneSetting>& scene_settings() {
  using T = SceneSetting::Type;
  static const std::vector<SceneSetting> settings = {{"cells", "tissue.cells", T::integer},
                                                     {"steps", "time.steps", T::integer},
                                                     {"dt", "time.dt", T::real},
                                                     {"cutoff", "cutoff", T::real},
                                                     {"seed", "seed", T::integer},
                                                     {"backend", "backend.name", T::text},
                                                     {"precision", "backend.precision", T::text},
                                                     {"platform", "backend.platform", T::text},
                                                     {"device", "backend.device", T::integer},
                                                     {"pair_exp", "backend.pair_exp", T::text},
                                                     {"policy", "decomposition.policy", T::text},
                                                     {"initial", "decomposition.initial", T::text},
                                                     {"rebalance_every", "decomposition.rebalance_every", T::integer},
                                                     {"timing", "decomposition.timing", T::text}};
  return settings;
}

const SceneSetting& scene_setting(const std::string& name) {
  for (const auto& s : scene_settings())
    if (name == s.name) return s;
  throw std::logic_error("scene_setting: '" + name + "' is not a scene setting");
}

std::string scene_override(const std::string& name, const std::string& value, const std::string& where) {
  const SceneSetting& s = scene_setting(name);
  if (s.type == SceneSetting::Type::integer) parse_integer(value, where);
  if (s.type == SceneSetting::Type::real) parse_real(value, where);
  return std::string(s.key) + "=" + value;
}

Scene load_scene(const std::string& file, const std::vector<std::string>& overrides,
                 const std::vector<std::string>& flags) {
  return parse_scene(read_file(file), file, overrides, flags);
}

}  // namespace semlb::engine
