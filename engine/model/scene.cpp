// Scene parsing: overrides on the YAML tree, then checked sections with line-accurate errors.
#include "scene.hpp"

#include <stdexcept>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "common/yaml.hpp"

namespace semlb::engine {

Section::Section(YAML::Node node, std::string path, std::string file, std::shared_ptr<const std::set<std::string>> overridden)
    : node_(std::move(node)), path_(std::move(path)), file_(std::move(file)), overridden_(std::move(overridden)) {}

std::string Section::where(const std::string& key) const {
  const std::string full = path_.empty() ? key : (key.empty() ? path_ : path_ + "." + key);
  if (overridden_) {  // a key set by --set, or inside a map given by --set (effects.noise={...}), is blamed on it
    std::string prefix;
    for (const auto& part : split(full, '.')) {
      prefix += (prefix.empty() ? "" : ".") + part;
      if (overridden_->count(prefix)) return "--set " + prefix + ": " + (prefix == full ? "" : "field '" + full + "': ");
    }
  }
  long line = 0;
  if (node_.IsMap() && at(key)) line = at(key).Mark().line + 1;
  else if (node_.IsDefined() && !node_.IsNull()) line = node_.Mark().line + 1;
  return semlb::where(file_, line, full);
}

void Section::fail(const std::string& key, const std::string& why) const { throw InputError(where(key) + why); }

YAML::Node Section::at(const std::string& key) const {
  const YAML::Node& n = node_;  // const access: a missing key must not be inserted
  return n[key];
}

bool Section::has(const std::string& key) const { return node_.IsMap() && at(key); }

double Section::real(const std::string& key, double fallback, double min, double max) const {
  read_.insert(key);
  if (!has(key)) return fallback;
  if (!at(key).IsScalar()) fail(key, "must be a number");
  return parse_real(at(key).Scalar(), where(key), min, max);
}

long Section::integer(const std::string& key, long fallback, long min, long max) const {
  read_.insert(key);
  if (!has(key)) return fallback;
  if (!at(key).IsScalar()) fail(key, "must be an integer");
  return parse_integer(at(key).Scalar(), where(key), min, max);
}

std::string Section::text(const std::string& key, const std::string& fallback) const {
  read_.insert(key);
  if (!has(key)) return fallback;
  if (!at(key).IsScalar()) fail(key, "must be a single value");
  return at(key).as<std::string>();
}

bool Section::boolean(const std::string& key, bool fallback) const {
  const std::string v = text(key, fallback ? "true" : "false");
  if (v != "true" && v != "false") fail(key, "must be true or false, got '" + v + "'");
  return v == "true";
}

std::vector<std::string> Section::texts(const std::string& key, const std::vector<std::string>& fallback) const {
  read_.insert(key);
  if (!has(key)) return fallback;
  if (at(key).IsScalar()) return {at(key).as<std::string>()};
  if (!at(key).IsSequence()) fail(key, "must be a list");
  std::vector<std::string> out;
  for (const auto& v : at(key)) out.push_back(v.as<std::string>());
  return out;
}

Section Section::child(const std::string& key) const {
  read_.insert(key);
  YAML::Node n = has(key) ? at(key) : YAML::Node(YAML::NodeType::Map);
  if (!n.IsMap() && !n.IsNull()) fail(key, "must be a map of settings");
  return Section(n.IsNull() ? YAML::Node(YAML::NodeType::Map) : n, path_.empty() ? key : path_ + "." + key, file_, overridden_);
}

std::vector<std::string> Section::keys() const {
  std::vector<std::string> out;
  if (node_.IsMap())
    for (const auto& kv : node_) out.push_back(kv.first.as<std::string>());
  return out;
}

void Section::finish() const {
  for (const auto& k : keys())
    if (!read_.count(k)) fail(k, "unknown setting");
}

namespace {

// Applies `a.b.c=value` to the tree, creating maps on the way; records the dotted path.
void apply_override(YAML::Node root, const std::string& assignment, std::set<std::string>& overridden) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--set " + assignment + ": expected KEY=VALUE");
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw InputError("--set " + path + ": value is not YAML: " + e.msg);
  }
  refuse_duplicate_keys(value, "--set " + path);
  std::vector<YAML::Node> chain{root};
  const auto parts = split(path, '.');
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (!next || next.IsNull()) chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
    else if (!next.IsMap()) throw InputError("--set " + path + ": '" + parts[i] + "' is not a map");
    chain.push_back(chain.back()[parts[i]]);
  }
  chain.back()[parts.back()] = value;
  overridden.insert(path);
}

void read_backend(const Section& s, BackendConfig& b) {
  b.name = s.text("name", b.name);
  b.precision = s.text("precision", b.precision);
  if (b.precision != "double" && b.precision != "float") s.fail("precision", "must be double or float");
  b.threads = static_cast<int>(s.integer("threads", 0, 0, 4096));
  b.platform = s.text("platform", "");
  b.device = static_cast<int>(s.integer("device", 0, 0, 1024));
  b.skin = s.real("skin", b.skin, 0, 1e3);
  s.finish();
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
  YAML::Node root = load_yaml(text, file, "scene");
  if (!root.IsMap()) throw InputError(file + ": a scene is a YAML map");
  auto overridden = std::make_shared<std::set<std::string>>();
  for (const auto& o : overrides) apply_override(root, o, *overridden);
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
  s.steps = time.integer("steps", s.steps, 0, 1L << 40);
  s.friction = time.real("friction", s.friction, 1e-12, 1e12);
  s.max_displacement = time.real("max_displacement", s.max_displacement, 1e-12, 1e12);
  s.cell_update_every = time.integer("cell_update_every", s.cell_update_every, 1, 1L << 30);
  time.finish();
  const Section output = top.child("output");
  s.snapshot_every = output.integer("snapshot_every", 0, 0, 1L << 40);
  s.log_every = output.integer("log_every", 100, 1, 1L << 40);
  s.checkpoint_every = output.integer("checkpoint_every", 0, 0, 1L << 40);
  s.record_workload = output.boolean("workload", false);
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
  static const std::vector<SceneSetting> settings = {
      {"cells", "tissue.cells", T::integer},          {"steps", "time.steps", T::integer},
      {"dt", "time.dt", T::real},                     {"cutoff", "cutoff", T::real},
      {"seed", "seed", T::integer},                   {"backend", "backend.name", T::text},
      {"precision", "backend.precision", T::text},    {"platform", "backend.platform", T::text},
      {"device", "backend.device", T::integer},       {"policy", "decomposition.policy", T::text},
      {"initial", "decomposition.initial", T::text},  {"rebalance_every", "decomposition.rebalance_every", T::integer},
      {"timing", "decomposition.timing", T::text}};
  return settings;
}

std::string scene_override(const std::string& name, const std::string& value, const std::string& where) {
  for (const auto& s : scene_settings())
    if (name == s.name) {
      if (s.type == SceneSetting::Type::integer) parse_integer(value, where);
      if (s.type == SceneSetting::Type::real) parse_real(value, where);
      return std::string(s.key) + "=" + value;
    }
  throw std::logic_error("scene_override: '" + name + "' is not a scene setting");
}

Scene load_scene(const std::string& file, const std::vector<std::string>& overrides) {
  return parse_scene(read_file(file), file, overrides);
}

}  // namespace semlb::engine
