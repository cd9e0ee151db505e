// A by-name registry filled by static registrar objects: policies, effects, backends, runners, launchers.
#pragma once
#include <cctype>
#include <map>
#include <string>
#include <vector>

namespace semlb {

// Entries by name, in name order. Use one per kind through a function-local static (registration runs
// during static initialisation, in any order). The callers keep their own error wording.
template <class T>
class Registry {
 public:
  void add(const std::string& name, T entry) { entries_[name] = std::move(entry); }
  // The entry registered under `name`, or nullptr.
  const T* find(const std::string& name) const {
    const auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : &it->second;
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

}  // namespace semlb
