// Small text-file helpers.
#include "text_io.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "errors.hpp"

namespace semlb {

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error(tmp + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> fields;
  size_t pos = 0;
  for (size_t at; (at = text.find(separator, pos)) != std::string::npos; pos = at + 1)
    fields.push_back(text.substr(pos, at - pos));
  fields.push_back(text.substr(pos));
  return fields;
}

}  // namespace semlb
