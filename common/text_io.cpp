// Small text helpers: files, splitting, strict numbers, round-trip reals.
#include "text_io.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "cleanup.hpp"
#include "errors.hpp"

namespace semlb {

PendingFile::PendingFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
  register_cleanup_path(tmp_);
}

PendingFile::~PendingFile() {
  if (!committed_) ::unlink(tmp_.c_str());  // no temporary file left; the path keeps its earlier contents
  unregister_cleanup_path(tmp_);
}

void PendingFile::commit() {
  if (::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw std::runtime_error(path_ + ": cannot rename " + tmp_ + " to it: " + std::strerror(errno));
  committed_ = true;
}

void write_file_atomically(const std::string& path, const std::string& text) {
  PendingFile pending(path);
  const std::string& tmp = pending.tmp();
  auto fail = [&](const std::string& what, int err) {
    throw std::runtime_error(path + ": " + what + ": " + std::strerror(err));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(path + ": cannot create " + tmp + ": " + std::strerror(errno));
  for (size_t at = 0; at < text.size();) {
    const ssize_t n = ::write(fd, text.data() + at, text.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      ::close(fd);
      fail("write failed", err);
    }
    at += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) fail("write failed", errno);
  pending.commit();
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string join(const std::vector<std::string>& fields, char separator) {
  std::string s;
  for (size_t i = 0; i < fields.size(); ++i) {
    if (i) s += separator;
    s += fields[i];
  }
  return s;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> fields;
  size_t pos = 0;
  for (size_t at; (at = text.find(separator, pos)) != std::string::npos; pos = at + 1)
    fields.push_back(text.substr(pos, at - pos));
  fields.push_back(text.substr(pos));
  return fields;
}

double parse_real(std::string_view text, const std::string& where, double min, double max, bool min_open,
                  bool max_open) {
  const std::string quoted = "'" + std::string(text) + "'";
  double v = 0;
  const char *first = text.data(), *last = text.data() + text.size();
  // from_chars takes no '+', no spaces and no "0x"; it does take "inf"/"nan", refused by the finiteness check.
  const auto [p, ec] = std::from_chars(first, last, v, std::chars_format::general);
  if (text.empty() || ec == std::errc::invalid_argument || p != last)
    throw InputError(where + quoted + " is not a number");
  if (ec == std::errc::result_out_of_range || !std::isfinite(v))
    throw InputError(where + quoted + " is not a finite number in the range of a double");
  if (v < min || v > max || (min_open && v == min) || (max_open && v == max))
    throw InputError(where + quoted + " is outside " + (min_open ? "(" : "[") + format_real(min) + ", " +
                     format_real(max) + (max_open ? ")" : "]"));
  return v;
}

long parse_integer(std::string_view text, const std::string& where, long min, long max) {
  const std::string quoted = "'" + std::string(text) + "'";
  long v = 0;
  const char *first = text.data(), *last = text.data() + text.size();
  const auto [p, ec] = std::from_chars(first, last, v);
  if (ec == std::errc::result_out_of_range) throw InputError(where + quoted + " does not fit a 64-bit integer");
  if (text.empty() || ec != std::errc() || p != last) {
    double unused = 0;  // say why a real was refused: integers are written as integers
    const auto [q, rc] = std::from_chars(first, last, unused, std::chars_format::general);
    if (!text.empty() && rc == std::errc() && q == last)
      throw InputError(where + quoted + " is not an integer (write integers without '.' or exponent)");
    throw InputError(where + quoted + " is not an integer");
  }
  const size_t digits = text[0] == '-' ? 1 : 0;  // "010" is 8 to a YAML 1.1 reader and 10 to us: refuse it
  if (text.size() > digits + 1 && text[digits] == '0')
    throw InputError(where + quoted + " has a leading zero (ambiguous: octal to some readers); write it without");
  if (v < min || v > max)
    throw InputError(where + quoted + " is outside [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  return v;
}

std::string format_real(double v) {
  char buf[64];
  const auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  if (ec != std::errc()) throw std::logic_error("format_real: buffer too small");
  return std::string(buf, p);
}

}  // namespace semlb
