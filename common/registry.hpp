// A by-name registry filled by static registrar objects: policies, effects, backends, runners, launchers.
#pragma once
#include <cctype>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace semlb {

// Entries by name, in name order. Use one per kind through a function-local static (registration runs
// during static initialisation, in any order). The callers keep their own error wording.
template <class T>
class Registry {
 public:
  // std::logic_error when `name` is registered already (two registrars of one name: a programming error).
  void add(const std::string& name, T entry) {
    if (!entries_.emplace(name, std::move(entry)).second) throw std::logic_error("'" + name + "' registered twice");
  }
  // The entry registered under `name`, or nullptr.
  const T* find(const std::string& name) const {
    const auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : &it->second;
  }
  // The entry registered under `name`; std::logic_error "no KIND 'NAME' (known: ...)" when there is none (the callers
  // whose names were checked already, e.g. a plug-in the effect registry found).
  const T& at(const std::string& kind, const std::string& name) const {
    if (const T* t = find(name)) return *t;
    throw std::logic_error("no " + kind + " '" + name + "' (known: " + known() + ")");
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, entry] : entries_) out.push_back(name);
    return out;
  }
  // "a, b, c": for "unknown X 'y' (known: a, b, c)" messages.
  std::string known() const {
    std::string out;
    for (const auto& [name, entry] : entries_) out += (out.empty() ? "" : ", ") + name;
    return out;
  }

 private:
  std::map<std::string, T> entries_;
};

// True when `name` is a C identifier ([A-Za-z_][A-Za-z0-9_]*): plug-ins whose name also names generated code (the
// OpenCL kernels of element terms and removal rules) are checked with it when they register.
inline bool is_c_identifier(const std::string& name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// The most parameters (reals) a plug-in with generated code takes: the size of its parameter buffer on a device.
inline constexpr size_t kMaxPluginParams = 64;

// The registration checks of such a plug-in (KIND "element term" or "removal rule"): std::logic_error unless `name`
// is a C identifier.
inline void check_plugin_name(const std::string& kind, const std::string& name) {
  if (!is_c_identifier(name)) throw std::logic_error(kind + " '" + name + "': not a C identifier");
}
// `params` (a plug-in's parameters read from its scene section), or std::logic_error when there are more than
// kMaxPluginParams.
inline std::vector<double> checked_plugin_params(const std::string& kind, const std::string& name, std::vector<double> params) {
  if (params.size() > kMaxPluginParams)
    throw std::logic_error(kind + " '" + name + "': more than " + std::to_string(kMaxPluginParams) + " parameters");
  return params;
}

}  // namespace semlb
