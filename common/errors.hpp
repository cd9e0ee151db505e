// Error types shared by every semlb module: InputError means "the user's input is wrong" (exit code 2).
#pragma once
#include <stdexcept>
#include <string>

namespace semlb {

// Bad input (file, flag, trace line, observation field). Messages are one line and name the culprit.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "FILE:LINE: field 'NAME': " prefix for messages about one field of one input line.
inline std::string where(const std::string& file, long line, const std::string& field) {
  std::string s = file;
  if (line > 0) s.append(":").append(std::to_string(line));
  if (!field.empty()) s.append(s.empty() ? "" : ": ").append("field '").append(field).append("'");
  return s.empty() ? s : s.append(": ");
}

}  // namespace semlb
