// The growth law or division rule a cell effect's section names (the `law` / `rule` key), read once: its name, its
// index in the registry's name order (what the cell stage's rules carry, physics/cells.h) and its parameters.
#pragma once
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/registry.hpp"
#include "model/scene.hpp"

namespace semlb::engine {

struct ChosenRule {
  std::string name;
  int index = -1;              // in registry.names()
  std::vector<double> params;  // at most SEMLB_CELL_RULE_PARAMS

  // Reads `key` of `s` (default `fallback`) as a name of the plug-in kind T (an InputError naming the field and the
  // known names otherwise), then the entry's parameters with its `read(s)`; std::logic_error when it derives more
  // than `max_params` (T::kKind names the kind in messages: "growth law", "division rule").
  template <class T>
  static ChosenRule read(const Section& s, const std::string& key, const std::string& fallback, size_t max_params) {
    const std::string kind = T::kKind;
    ChosenRule c;
    c.name = s.text(key, fallback);
    const T* entry = PluginKind<T>::find(c.name);
    if (!entry) s.fail(key, "'" + c.name + "' is not a " + kind + " (known: " + PluginKind<T>::known() + ")");
    c.index = PluginKind<T>::index(c.name);
    c.params = entry->read(s);
    if (c.params.size() > max_params)
      throw std::logic_error(kind + " '" + c.name + "': more than " + std::to_string(max_params) + " parameters");
    return c;
  }
};

}  // namespace semlb::engine
