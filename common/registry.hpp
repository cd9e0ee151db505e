// A by-name registry filled by static registrar objects, one per plug-in kind (PluginKind: policies, effects, backends,
// runners, launchers, cell fields, the engine's terms and cell rules), and the catalogue of the kinds that `semlb list`
// shows (listed_kinds).
#pragma once
#include <algorithm>
#include <cctype>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
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

// Every kind `semlb list` shows, by the name it is listed under ("pair-terms"), with the function that gives its names:
// each PluginKind adds itself when its first entry registers; a list that is no registry (the cell types by index)
// adds itself with a ListedKind.
using KindNames = std::vector<std::string> (*)();
Registry<KindNames>& listed_kinds();
struct ListedKind {
  ListedKind(const std::string& kind, KindNames names) { listed_kinds().add(kind, names); }
};

namespace detail {
template <class T, class = void>
struct has_registering : std::false_type {};
template <class T>
struct has_registering<
    T, std::void_t<decltype(T::registering(std::declval<const std::string&>(), std::declval<const T&>()))>>
    : std::true_type {};
}  // namespace detail

// One plug-in kind: the entries T (what a plug-in of the kind registers) by name, filled at static initialisation by
// Registrar<T>. T names its kind with two members, and may check each registration with a third:
//   static constexpr const char* kKind = "pair term";     // in messages: "no pair term 'x' (known: a, b)"
//   static constexpr const char* kListed = "pair-terms";  // its name in `semlb list`
//   static void registering(const std::string& name, const T& entry);  // optional: run before the entry is added
//                                                                       // (checks; an effect of the same name)
template <class T>
class PluginKind {
 public:
  static void add(const std::string& name, T entry) {
    if constexpr (detail::has_registering<T>::value) T::registering(name, entry);
    entries().add(name, std::move(entry));
  }
  // The entry registered under `name`, or nullptr.
  static const T* find(const std::string& name) { return entries().find(name); }
  // The entry registered under `name`; std::logic_error "no KIND 'NAME' (known: ...)" when there is none (for names
  // checked already: a scene's names are checked where they are read, with the file and line).
  static const T& at(const std::string& name) { return entries().at(T::kKind, name); }
  // The registered names, in name order.
  static std::vector<std::string> names() { return entries().names(); }
  // "a, b, c": for "unknown X 'y' (known: a, b, c)" messages.
  static std::string known() { return entries().known(); }
  // The position of `name` in names() (what generated code dispatches on), or -1.
  static int index(const std::string& name) {
    const auto all = names();
    const auto it = std::find(all.begin(), all.end(), name);
    return it == all.end() ? -1 : static_cast<int>(it - all.begin());
  }

 private:
  static Registry<T>& entries() {
    static Registry<T> r = (listed_kinds().add(T::kListed, &PluginKind::names), Registry<T>{});
    return r;
  }
};

// A plug-in file registers itself with one line at namespace scope, whatever its kind:
//   const Registrar<PairTerm> registrar("mechanics", {10, read, ...});
// std::logic_error when the name is registered twice or T::registering refuses it.
template <class T>
struct Registrar {
  Registrar(const std::string& name, T entry) { PluginKind<T>::add(name, std::move(entry)); }
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
inline std::vector<double> checked_plugin_params(const std::string& kind, const std::string& name,
                                                 std::vector<double> params) {
  if (params.size() > kMaxPluginParams)
    throw std::logic_error(kind + " '" + name + "': more than " + std::to_string(kMaxPluginParams) + " parameters");
  return params;
}

}  // namespace semlb
