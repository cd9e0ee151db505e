// The one reader of typed settings (scenes, manifest rows, policy parameters, training configs): key -> text with
// the place it came from; strict typed reads with ranges, unread-key detection and the one error prefix.
#pragma once
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace semlb {

// Where a value came from: line `line` of `file`, or (`flag` non-empty) a command-line flag or other source
// named in words ("--set ranks", "--ranks", "policy parameter 'tau'").
struct Origin {
  std::string file;
  long line = 0;  // 1-based; 0: the file as a whole
  std::string flag;
  // The field the flag set when it set a whole map ("--set effects.noise={...}"): a field inside it is named too.
  std::string flag_field;
};

// The prefix of every message about `field`'s value: "FILE:LINE: field 'FIELD': " (semlb::where) for a file,
// "FLAG: " for a flag, "FLAG: field 'FIELD': " for a field inside a map the flag set (FIELD != flag_field).
std::string where(const Origin& origin, const std::string& field);

// Typed, checked access to one map of settings. Each key has one value: a single text, a list of texts or a
// map (read by its owner, e.g. engine::Section::child) with its Origin. Reading a key (present or not) marks
// it read; finish() refuses keys nobody read. Every error is an InputError "<where(key)><why>", one line.
// Fields are named by their dotted path: path() + "." + key.
class Settings {
 public:
  enum class Kind { text, list, map, none };  // none: a YAML null ("key:" with no value)
  struct Value {
    Kind kind = Kind::text;
    std::string text;                // kind text
    std::vector<std::string> items;  // kind list
    Origin origin;
  };

  // `path`: the dotted path of this map ("" at the top); `fallback`: where a key that is not set is blamed.
  explicit Settings(std::string path = "", Origin fallback = {});

  // Sets KEY (replacing an earlier value, which keeps its place in key order).
  void set(const std::string& key, Value value);
  void set(const std::string& key, const std::string& text, const Origin& origin);
  bool has(const std::string& key) const { return find(key) != nullptr; }
  const Value* find(const std::string& key) const;
  std::vector<std::string> keys() const;  // in the order first set

  // KEY parsed strictly (parse_real, common/text_io.hpp) in [min, max], an end open when min_open / max_open
  // ("'0' is outside (0, 2]"); FALLBACK when not set. A list or map: "must be a number".
  double real(const std::string& key, double fallback, double min = -std::numeric_limits<double>::max(),
              double max = std::numeric_limits<double>::max(), bool min_open = false, bool max_open = false) const;
  // KEY parsed strictly as an integer (parse_integer: "2.0" is refused) in [min, max]; FALLBACK when not set.
  long integer(const std::string& key, long fallback, long min = std::numeric_limits<long>::min(),
               long max = std::numeric_limits<long>::max()) const;
  // KEY's text as written; FALLBACK when not set. A list or map: "must be a single value".
  std::string text(const std::string& key, const std::string& fallback) const;
  // Exactly "true" or "false" ("must be true or false, got 'yes'"); FALLBACK when not set.
  bool boolean(const std::string& key, bool fallback) const;
  // A list's texts, or a single text as a list of one; FALLBACK when not set. A map: "must be a list".
  std::vector<std::string> texts(const std::string& key, const std::vector<std::string>& fallback) const;

  void mark_read(const std::string& key) const { read_.insert(key); }
  std::vector<std::string> unread() const;  // in key order
  // Throws "<where(first unread key)><why>" ("FILE:3: field 'tiem': unknown setting").
  void finish(const std::string& why = "unknown setting") const;

  const std::string& path() const { return path_; }
  std::string field(const std::string& key) const;  // path.key; the path itself for key ""
  // Where KEY's value came from (the fallback when not set).
  const Origin& origin(const std::string& key) const;
  std::string where(const std::string& key) const { return semlb::where(origin(key), field(key)); }
  [[noreturn]] void fail(const std::string& key, const std::string& why) const;

 private:
  std::string path_;
  Origin fallback_;
  std::vector<std::pair<std::string, Value>> values_;  // small maps: a linear search keeps file order
  mutable std::set<std::string> read_;
};

}  // namespace semlb
