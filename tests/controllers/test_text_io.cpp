// Text helpers: field splitting keeps empty fields; atomic writes leave no temporary behind.
#include <gtest/gtest.h>

#include <filesystem>

#include "controllers/errors.hpp"
#include "controllers/text_io.hpp"

using namespace semlb;

TEST(TextIo, SplitKeepsEmptyFields) {
  EXPECT_EQ(split("a,,b", ','), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(split("a,", ','), (std::vector<std::string>{"a", ""}));
  EXPECT_EQ(split("", ','), (std::vector<std::string>{""}));
}

TEST(TextIo, AtomicWriteRoundTripsAndMissingFilesAreInputErrors) {
  const auto path = (std::filesystem::temp_directory_path() / "semlb_text_io.txt").string();
  write_file_atomically(path, "one\ntwo\n");
  EXPECT_EQ(read_file(path), "one\ntwo\n");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  std::filesystem::remove(path);
  EXPECT_THROW(read_file(path), InputError);
}
