// The one settings reader: typed reads, ranges, unread keys and the error prefix, written once.
#include "settings.hpp"

#include "errors.hpp"
#include "text_io.hpp"

namespace semlb {

std::string where(const Origin& origin, const std::string& field) {
  if (origin.flag.empty()) return where(origin.file, origin.line, field);
  const bool inside = !origin.flag_field.empty() && origin.flag_field != field;
  return origin.flag + ": " + (inside ? "field '" + field + "': " : "");
}

Settings::Settings(std::string path, Origin fallback) : path_(std::move(path)), fallback_(std::move(fallback)) {}

void Settings::set(const std::string& key, Value value) {
  for (auto& [k, v] : values_)
    if (k == key) {
      v = std::move(value);
      return;
    }
  values_.emplace_back(key, std::move(value));
}

void Settings::set(const std::string& key, const std::string& text, const Origin& origin) {
  set(key, Value{Kind::text, text, {}, origin});
}

const Settings::Value* Settings::find(const std::string& key) const {
  for (const auto& [k, v] : values_)
    if (k == key) return &v;
  return nullptr;
}

std::vector<std::string> Settings::keys() const {
  std::vector<std::string> out;
  for (const auto& kv : values_) out.push_back(kv.first);
  return out;
}

double Settings::real(const std::string& key, double fallback, double min, double max, bool min_open,
                      bool max_open) const {
  mark_read(key);
  const Value* v = find(key);
  if (!v) return fallback;
  if (v->kind != Kind::text) fail(key, "must be a number");
  return parse_real(v->text, where(key), min, max, min_open, max_open);
}

long Settings::integer(const std::string& key, long fallback, long min, long max) const {
  mark_read(key);
  const Value* v = find(key);
  if (!v) return fallback;
  if (v->kind != Kind::text) fail(key, "must be an integer");
  return parse_integer(v->text, where(key), min, max);
}

std::string Settings::text(const std::string& key, const std::string& fallback) const {
  mark_read(key);
  const Value* v = find(key);
  if (!v) return fallback;
  if (v->kind != Kind::text) fail(key, "must be a single value");
  return v->text;
}

bool Settings::boolean(const std::string& key, bool fallback) const {
  const std::string v = text(key, fallback ? "true" : "false");
  if (v != "true" && v != "false") fail(key, "must be true or false, got '" + v + "'");
  return v == "true";
}

std::vector<std::string> Settings::texts(const std::string& key, const std::vector<std::string>& fallback) const {
  mark_read(key);
  const Value* v = find(key);
  if (!v) return fallback;
  if (v->kind == Kind::text) return {v->text};
  if (v->kind != Kind::list) fail(key, "must be a list");
  return v->items;
}

std::vector<std::string> Settings::unread() const {
  std::vector<std::string> out;
  for (const auto& kv : values_)
    if (!read_.count(kv.first)) out.push_back(kv.first);
  return out;
}

void Settings::finish(const std::string& why) const {
  for (const auto& k : unread()) fail(k, why);
}

std::string Settings::field(const std::string& key) const {
  return path_.empty() ? key : (key.empty() ? path_ : path_ + "." + key);
}

const Origin& Settings::origin(const std::string& key) const {
  const Value* v = key.empty() ? nullptr : find(key);
  return v ? v->origin : fallback_;
}

void Settings::fail(const std::string& key, const std::string& why) const { throw InputError(where(key) + why); }

}  // namespace semlb
