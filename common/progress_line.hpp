// The one status line of long runs (sweep, Slurm sweep, trainer, semlb sim): how it is drawn on a terminal and in a
// log.
#pragma once
#include <cstdio>
#include <mutex>
#include <string>

namespace semlb {

// A status line on a stream (stderr by default). On a terminal each show() rewrites the line in place ("\r" TEXT, no
// newline) and note() prints a line of its own below it; elsewhere (a log, a pipe) every shown text is a line of its
// own, so logs keep every state. Off (on = false): every call prints nothing. Safe to call from several threads.
class ProgressLine {
 public:
  // A line on OUT; a terminal when OUT is one (isatty).
  explicit ProgressLine(bool on, std::FILE* out = stderr);
  // The same with the terminal decided by the caller (tests).
  ProgressLine(bool on, std::FILE* out, bool tty);
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  bool on() const { return on_; }
  bool tty() const { return tty_; }
  // TEXT (one line, no newline in it) as the status line. Terminal: "\r" TEXT, left open for the next show() unless
  // `last` (the final state, or a line that is to stay: it then ends with a newline). Elsewhere: TEXT and a newline.
  void show(const std::string& text, bool last = false);
  // TEXT as a line of its own: an open terminal line is ended first; TEXT then ends with a newline.
  void note(const std::string& text);
  // Ends an open terminal line with a newline; nothing when none is open.
  void close();

 private:
  bool on_, tty_;
  std::FILE* out_;
  bool open_ = false;  // a terminal line shown and not yet ended
  std::mutex mu_;
};

// Seconds still to go at the rate so far: elapsed / done x left (elapsed in s, done and left in any one unit: jobs,
// steps); 0 while nothing is done.
double eta_seconds(double elapsed, double done, double left);

// printf into a string (the status texts keep their printf formats, e.g. "%.1f s").
std::string format_text(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace semlb
