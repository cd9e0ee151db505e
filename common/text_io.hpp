// Small text helpers shared by every module: atomic writes, whole-file reads, field splitting, and the ONE
// strict number parser / real formatter (input rules: docs/engine.md "Input rules").
#pragma once
#include <algorithm>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace semlb {

// PATH.tmp while a writer fills it, renamed onto PATH by commit(): until then a signal's cleanup (common/cleanup.hpp)
// and every way out of the writer's scope remove it, so PATH is whole or keeps its earlier contents. commit() throws
// std::runtime_error "PATH: cannot rename PATH.tmp to it: REASON". The one place the atomic writers (text, HDF5) share.
class PendingFile {
 public:
  explicit PendingFile(std::string path);
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;
  ~PendingFile();
  const std::string& tmp() const { return tmp_; }
  void commit();

 private:
  std::string path_, tmp_;
  bool committed_ = false;
};

// Writes PATH.tmp and renames it onto PATH (PendingFile), so readers never see a half-written file.
void write_file_atomically(const std::string& path, const std::string& text);
// The whole file; throws InputError if it cannot be opened.
std::string read_file(const std::string& path);
// Fields between separators, empty ones kept: split("a,,b", ',') = {"a", "", "b"}; split("", ',') = {""}.
std::vector<std::string> split(const std::string& text, char separator);
// The inverse: fields joined by the separator, join({"a", "", "b"}, ',') = "a,,b"; join({}, ',') = "".
std::string join(const std::vector<std::string>& fields, char separator = ',');

// Strict number parsing, used wherever a number is read from text. The whole token must be the number:
// no surrounding spaces, no units ("0.15mm"), no hex ("0x10"), no leading '+', no "inf"/"nan"; a real is
// finite (1e400 is refused) and an integer is written as an integer ("2.0", "1e3" are refused) that fits a
// long. The value must lie in [min, max] (for a real, an end is open when min_open / max_open). `where` prefixes
// the message (e.g. semlb::where(file, line, field), or "--set KEY: "); errors throw
// InputError("<where>'<text>' is not a number", ... "is outside [a, b]", "is outside (a, b]").
double parse_real(std::string_view text, const std::string& where, double min = -std::numeric_limits<double>::max(),
                  double max = std::numeric_limits<double>::max(), bool min_open = false, bool max_open = false);
long parse_integer(std::string_view text, const std::string& where, long min = std::numeric_limits<long>::min(),
                   long max = std::numeric_limits<long>::max());

// The shortest text that reads back as exactly `v` (std::to_chars): 12345.01 -> "12345.01", 0.1 -> "0.1",
// 3 -> "3", 1e-07 -> "1e-07". Used for every real written into CSV, XDMF and other text outputs.
std::string format_real(double v);

// The rows of a comma-separated file that semlb wrote (a header line, no quoting), each by column name; empty lines
// skipped. std::runtime_error naming the file when one of `columns` is not in its header (a file of another version).
template <class Names = std::vector<std::string>>
std::vector<std::map<std::string, std::string>> csv_rows(const std::string& path, const Names& columns = {}) {
  const auto lines = split(read_file(path), '\n');
  const auto header = split(lines[0], ',');
  for (const auto& c : columns)
    if (std::find(header.begin(), header.end(), c) == header.end())
      throw std::runtime_error(path + ": no column '" + std::string(c) + "' in its header '" + lines[0] + "'");
  std::vector<std::map<std::string, std::string>> rows;
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const auto f = split(lines[i], ',');
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < header.size() && c < f.size(); ++c) row[header[c]] = f[c];
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace semlb
