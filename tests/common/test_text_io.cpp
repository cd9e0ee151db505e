// Text helpers: field splitting keeps empty fields; atomic writes leave no temporary behind.
#include <gtest/gtest.h>

#include "../run_command.hpp"

#include <cstdlib>
#include <filesystem>

#include "common/errors.hpp"
#include "common/text_io.hpp"

using namespace semlb;

TEST(TextIo, SplitKeepsEmptyFields) {
  EXPECT_EQ(split("a,,b", ','), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(split("a,", ','), (std::vector<std::string>{"a", ""}));
  EXPECT_EQ(split("", ','), (std::vector<std::string>{""}));
  EXPECT_EQ(join({"a", "", "b"}, ','), "a,,b");  // the inverse of split
  EXPECT_EQ(join(split("x;y;", ';'), ';'), "x;y;");
  EXPECT_EQ(join({}, ','), "");
}

TEST(TextIo, AtomicWriteRoundTripsAndMissingFilesAreInputErrors) {
  const auto path = semlb::test::fresh_dir("text_io") + "/semlb_text_io.txt";
  write_file_atomically(path, "one\ntwo\n");
  EXPECT_EQ(read_file(path), "one\ntwo\n");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  std::filesystem::remove(path);
  EXPECT_THROW(read_file(path), InputError);
}

// The one strict number parser: the whole token, finite, in range; integers written as integers.
TEST(TextIo, ParseRealRefusesEverythingButAWholeFiniteNumber) {
  for (const char* bad :
       {"0.15mm", "100um", "inf", "-inf", "nan", "1e400", " 5", "5 ", "0x10", "+5", "", "5,0", "1e", "."}) {
    try {
      parse_real(bad, "F:3: field 'x': ");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("F:3: field 'x': '" + std::string(bad) + "'", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(parse_real("0.15", ""), 0.15);
  EXPECT_EQ(parse_real("-2.5e-3", ""), -2.5e-3);
  EXPECT_EQ(parse_real("100", ""), 100.0);
  EXPECT_EQ(parse_real("1E3", ""), 1000.0);
  EXPECT_THROW(parse_real("1.5", "", 0.0, 1.0), InputError);
  EXPECT_EQ(parse_real("1", "", 0.0, 1.0), 1.0);
  try {  // an open end refuses the end itself and says so
    parse_real("0", "w: ", 0.0, 2.0, true, true);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "w: '0' is outside (0, 2)");
  }
  EXPECT_EQ(parse_real("2", "", 0.0, 2.0, true), 2.0);
}

TEST(TextIo, ParseIntegerRefusesRealsOverflowAndTrailingText) {
  for (const char* bad : {"2.5", "2.0", "1e3", "9223372036854775808", "-9223372036854775809", " 5", "5 ", "0x10", "+5",
                          "", "5x", "inf", "nan"})
    EXPECT_THROW(parse_integer(bad, "w: "), InputError) << bad;
  EXPECT_EQ(parse_integer("9223372036854775807", ""), 9223372036854775807L);
  EXPECT_EQ(parse_integer("-12", ""), -12);
  EXPECT_EQ(parse_integer("0", "", 0, 5), 0);
  EXPECT_THROW(parse_integer("6", "", 0, 5), InputError);
  try {
    parse_integer("2.0", "--set steps: ");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--set steps: '2.0' is not an integer"), std::string::npos) << e.what();
  }
}

TEST(TextIo, ParseIntegerRefusesLeadingZeros) {
  EXPECT_EQ(parse_integer("0", "x: "), 0);
  EXPECT_EQ(parse_integer("-0", "x: "), 0);
  EXPECT_EQ(parse_integer("100", "x: "), 100);
  EXPECT_EQ(parse_integer("-7", "x: "), -7);
  for (const char* bad : {"010", "00", "-01", "0007"}) EXPECT_THROW(parse_integer(bad, "x: "), InputError) << bad;
}

TEST(TextIo, FormatRealRoundTripsAndKeepsNearbyTimesApart) {
  for (double v : {12345.01, 12345.02, 12345.03, 0.1, 1.0 / 3.0, 1e-300, 5e-324, 1.7976931348623157e308, -0.0, 3.0,
                   123456789.123456789})
    EXPECT_EQ(std::strtod(format_real(v).c_str(), nullptr), v) << format_real(v);
  EXPECT_EQ(format_real(12345.01), "12345.01");
  EXPECT_NE(format_real(12345.02), format_real(12345.03));
  EXPECT_EQ(format_real(3.0), "3");
  EXPECT_EQ(format_real(0.25), "0.25");
}
