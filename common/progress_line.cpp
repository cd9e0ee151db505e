// ProgressLine: the status line of long runs (sweep, Slurm sweep, trainer).
#include "progress_line.hpp"

#include <unistd.h>

#include <cstdarg>
#include <vector>

namespace semlb {

ProgressLine::ProgressLine(bool on, std::FILE* out) : ProgressLine(on, out, isatty(fileno(out)) != 0) {}

ProgressLine::ProgressLine(bool on, std::FILE* out, bool tty) : on_(on), tty_(tty), out_(out) {}

void ProgressLine::show(const std::string& text, bool last) {
  if (!on_) return;
  std::lock_guard lock(mu_);
  std::fprintf(out_, "%s%s%s", tty_ ? "\r" : "", text.c_str(), tty_ && !last ? "" : "\n");
  std::fflush(out_);
  open_ = tty_ && !last;
}

void ProgressLine::note(const std::string& text) {
  if (!on_) return;
  std::lock_guard lock(mu_);
  std::fprintf(out_, "%s%s\n", open_ ? "\n" : "", text.c_str());
  std::fflush(out_);
  open_ = false;
}

void ProgressLine::close() {
  if (!on_) return;
  std::lock_guard lock(mu_);
  if (open_) std::fputc('\n', out_);
  std::fflush(out_);
  open_ = false;
}

double eta_seconds(double elapsed, double done, double left) { return done > 0 ? elapsed / done * left : 0.0; }

std::string format_text(const char* format, ...) {
  va_list args, copy;
  va_start(args, format);
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::vector<char> buf(static_cast<size_t>(n > 0 ? n : 0) + 1);
  std::vsnprintf(buf.data(), buf.size(), format, args);
  va_end(args);
  return std::string(buf.data(), static_cast<size_t>(n > 0 ? n : 0));
}

}  // namespace semlb
