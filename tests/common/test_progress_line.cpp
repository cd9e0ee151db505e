// ProgressLine (common/progress_line.hpp): the bytes a status line writes on a terminal and in a log, and its ETA.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "common/progress_line.hpp"

using namespace semlb;

namespace {
// Everything written to F since it was opened.
std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string out;
  for (int c; (c = std::fgetc(f)) != EOF;) out += static_cast<char>(c);
  return out;
}

// The bytes of: show a, show b, note n, show c, show d (last), close.
std::string sequence(bool on, bool tty) {
  std::FILE* f = std::tmpfile();
  {
    ProgressLine line(on, f, tty);
    line.show("a");
    line.show("b");
    line.note("n");
    line.show("c");
    line.show("d", true);
    line.close();
  }
  const std::string out = contents(f);
  std::fclose(f);
  return out;
}
}  // namespace

// A terminal rewrites the line in place and ends it only for a note, a last line or close(); a log gets every text as a
// line; off writes nothing.
TEST(ProgressLine, TerminalRewritesInPlaceALogGetsLines) {
  EXPECT_EQ(sequence(true, true), "\ra\rb\nn\n\rc\rd\n");
  EXPECT_EQ(sequence(true, false), "a\nb\nn\nc\nd\n");
  EXPECT_EQ(sequence(false, true), "");
  EXPECT_EQ(sequence(false, false), "");
}

// close() ends an open terminal line once; with nothing open it writes nothing.
TEST(ProgressLine, CloseEndsAnOpenLineOnce) {
  std::FILE* f = std::tmpfile();
  {
    ProgressLine line(true, f, true);
    line.close();
    line.show("x");
    line.close();
    line.close();
    line.note("y");  // nothing open: no empty line before it
  }
  EXPECT_EQ(contents(f), "\rx\ny\n");
  std::fclose(f);
}

TEST(ProgressLine, EtaAndFormat) {
  EXPECT_DOUBLE_EQ(eta_seconds(10.0, 4.0, 6.0), 15.0);  // 2.5 s per unit, 6 left
  EXPECT_EQ(eta_seconds(10.0, 0.0, 6.0), 0.0);
  EXPECT_EQ(format_text("[%s] %zu/%zu jobs  %.1f s", "demo", size_t{3}, size_t{40}, 12.04), "[demo] 3/40 jobs  12.0 s");
  EXPECT_EQ(format_text("%s", std::string(5000, 'x').c_str()).size(), 5000u);  // longer than any fixed buffer
}
