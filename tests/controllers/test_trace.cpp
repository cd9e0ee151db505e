// Trace lines: round trip and one-line errors naming the file, line and field.
#include <gtest/gtest.h>

#include "common/errors.hpp"
#include "controllers/trace.hpp"

using namespace semlb;

namespace {
std::string error_of(const std::string& line) {
  try {
    parse_trace_line(line, "t.jsonl", 7);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Trace, RoundTripsAnObservation) {
  TraceEvent e;
  e.obs.event = 3;
  e.obs.slices = 12;
  e.obs.min_width = 2;
  e.obs.boundaries = {4, 8};
  e.obs.times = {1.0 / 3.0, 1.1, 0.9};
  e.obs.slice_work = std::vector<double>(12, 0.1);
  e.obs.growth_phase = 0.3;
  e.obs.growth_event = true;
  e.decision = std::vector<int>{5, 8};
  const auto back = parse_trace_line(to_json(e).dump(), "t.jsonl", 1);
  EXPECT_EQ(back.obs.times, e.obs.times);  // doubles survive bit for bit
  EXPECT_EQ(back.obs.boundaries, e.obs.boundaries);
  EXPECT_EQ(back.obs.slice_work, e.obs.slice_work);
  EXPECT_TRUE(back.obs.oracle_work.empty());
  EXPECT_EQ(*back.decision, *e.decision);
  EXPECT_TRUE(back.obs.growth_event);
}

TEST(Trace, ErrorsNameFileLineAndField) {
  const std::string ok = R"("event":0,"slices":256,"min_width":4,"boundaries":[64,128,192])";
  EXPECT_EQ(error_of("{" + ok + R"(,"times":[1.0,1.1,0.9,1.0]})"), "");
  EXPECT_EQ(error_of("{" + ok + "}"), "t.jsonl:7: field 'times': missing");
  EXPECT_EQ(error_of("{" + ok + R"(,"times":"fast"})"), "t.jsonl:7: field 'times': has the wrong type (string)");
  EXPECT_NE(error_of("{" + ok + R"(,"times":[1,1,-1,1]})").find("t.jsonl:7: field 'times': event 0: times[2]"),
            std::string::npos);
  EXPECT_NE(error_of("{" + ok + R"(,"times":[1,1,1]})").find("boundaries has 3 entries but times has 3"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"event":0,"slices":10,"min_width":4,"boundaries":[3],"times":[1,1]})").find("width 3"),
            std::string::npos);
  EXPECT_EQ(error_of("{\"event\":"), "t.jsonl:7: not valid JSON (byte 10)");
  EXPECT_NE(error_of("{" + ok + R"(,"times":[1,1,1,1],"slice_work":[1,2]})").find("slice_work has 2 entries"),
            std::string::npos);
}

// Numbers in traces are strict: an integer field written 2.0 or 2.5 is refused (nlohmann would truncate),
// a real that overflows to inf is refused, an integer beyond int is refused.
TEST(Trace, NumbersAreStrict) {
  const std::string tail = R"(,"boundaries":[64,128,192],"times":[1.0,1.1,0.9,1.0]})";
  EXPECT_EQ(error_of(R"({"event":0,"slices":256,"min_width":4)" + tail), "");
  EXPECT_EQ(error_of(R"({"event":0,"slices":256.5,"min_width":4)" + tail),
            "t.jsonl:7: field 'slices': 256.5 is not an integer");
  EXPECT_EQ(error_of(R"({"event":0,"slices":256.0,"min_width":4)" + tail),
            "t.jsonl:7: field 'slices': 256.0 is not an integer");
  EXPECT_EQ(error_of(R"({"event":4294967296,"slices":256,"min_width":4)" + tail),
            "t.jsonl:7: field 'event': 4294967296 does not fit a 32-bit integer");
  EXPECT_EQ(error_of(R"({"event":0,"slices":256,"min_width":4,"boundaries":[64,128.5,192],"times":[1,1,1,1]})"),
            "t.jsonl:7: field 'boundaries': item 1: 128.5 is not an integer");
  const std::string head = R"({"event":0,"slices":256,"min_width":4,"boundaries":[64,128,192],)";
  EXPECT_EQ(error_of(head + R"("times":[1,1e400,1,1]})"),
            "t.jsonl:7: a number does not fit a double (numbers must be finite)");
  EXPECT_EQ(error_of(head + R"("times":[1,1,1,1],"growth_phase":-1e999})"),
            "t.jsonl:7: a number does not fit a double (numbers must be finite)");
  EXPECT_EQ(error_of(head + R"("times":[1,1,1,1],"growth_event":1})"),
            "t.jsonl:7: field 'growth_event': has the wrong type (number)");
}
