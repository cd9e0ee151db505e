// Strict YAML loading shared by scenes, manifests and training configs: syntax errors and duplicate keys
// (which yaml-cpp would silently resolve to the first) are one-line InputErrors naming file, line and key.
#pragma once
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "common/errors.hpp"
#include "common/settings.hpp"
#include "common/text_io.hpp"

namespace semlb {

// Throws InputError "FILE:LINE: FIELD: duplicate key (first at line L)" for the first map, depth first, that
// names a key twice. `path` is the dotted path of `node` (empty at the root).
inline void refuse_duplicate_keys(const YAML::Node& node, const std::string& file, const std::string& path = "") {
  if (node.IsSequence())
    for (const auto& item : node) refuse_duplicate_keys(item, file, path);
  if (!node.IsMap()) return;
  std::vector<std::pair<std::string, long>> seen;  // small maps: a linear search keeps file order
  for (const auto& kv : node) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : YAML::Dump(kv.first);
    const std::string full = path.empty() ? key : path + "." + key;
    const long line = kv.first.Mark().line + 1;
    for (const auto& [k, first] : seen)
      if (k == key)
        throw InputError(where(file, line, full) + "duplicate key (first at line " + std::to_string(first) + ")");
    seen.emplace_back(key, line);
    refuse_duplicate_keys(kv.second, file, full);
  }
}

// Parses `text` (the contents of `file`; `what` names the kind of file in the syntax error) strictly.
inline YAML::Node load_yaml(const std::string& text, const std::string& file, const std::string& what) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(where(file, e.mark.line + 1, "") + "YAML syntax error in " + what + ": " + e.msg);
  }
  refuse_duplicate_keys(root, file);
  return root;
}

// Reads and parses `file` strictly; an unreadable file is "FILE: cannot open WHAT".
inline YAML::Node load_yaml_file(const std::string& file, const std::string& what) {
  std::string text;
  try {
    text = read_file(file);
  } catch (const std::exception&) {
    throw InputError(file + ": cannot open " + what);
  }
  return load_yaml(text, file, what);
}

// A flat config (a YAML mapping of KEY: VALUE, e.g. a training or fit config; `what` names the kind in errors) as
// Settings, each value blamed on its file and line, then each "KEY=VALUE" of `overrides` over it, blamed on "--set
// KEY". An empty `path` gives the overrides alone. InputError on a file that is not a mapping or an override without
// "=". A nested value is kept as a map, so reading it as a value fails naming its field.
inline Settings load_flat_settings(const std::string& path, const std::string& what,
                                   const std::vector<std::string>& overrides) {
  Settings s("", Origin{path, 0, "", ""});
  if (!path.empty()) {
    const YAML::Node root = load_yaml_file(path, what);
    if (root && !root.IsNull()) {
      if (!root.IsMap()) throw InputError(path + ": a " + what + " must be a YAML mapping");
      for (const auto& kv : root) {
        const Origin at{path, kv.first.Mark().line + 1, "", ""};
        s.set(kv.first.Scalar(), Settings::Value{kv.second.IsScalar() ? Settings::Kind::text : Settings::Kind::map,
                                                 kv.second.IsScalar() ? kv.second.Scalar() : "",
                                                 {},
                                                 at});
      }
    }
  }
  for (const auto& o : overrides) {
    const size_t eq = o.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set: '" + o + "' is not KEY=VALUE");
    s.set(o.substr(0, eq), o.substr(eq + 1), Origin{"", 0, "--set " + o.substr(0, eq), ""});
  }
  return s;
}

}  // namespace semlb
