// Small text-file helpers shared by every module: atomic writes, whole-file reads, field splitting.
#pragma once
#include <string>
#include <vector>

namespace semlb {

// Writes PATH.tmp and renames it onto PATH, so readers never see a half-written file.
void write_file_atomically(const std::string& path, const std::string& text);
// The whole file; throws InputError if it cannot be opened.
std::string read_file(const std::string& path);
// Fields between separators, empty ones kept: split("a,,b", ',') = {"a", "", "b"}; split("", ',') = {""}.
std::vector<std::string> split(const std::string& text, char separator);

}  // namespace semlb
