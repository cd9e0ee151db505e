// Partition model: widths, validity errors, the min-width truncation sweep, migration.
#include <gtest/gtest.h>

#include "common/errors.hpp"
#include "controllers/partition.hpp"

using namespace semlb;

TEST(Partition, WidthsAndUniform) {
  EXPECT_EQ(widths(std::vector<int>{3, 7}, 10), (std::vector<int>{3, 4, 3}));
  EXPECT_EQ(uniform_partition(4, 10), (std::vector<int>{2, 5, 7}));
  EXPECT_TRUE(uniform_partition(1, 10).empty());
}

TEST(Partition, CheckRejectsNarrowAndTooManyRanks) {
  EXPECT_NO_THROW(check_partition(std::vector<int>{4, 8}, 12, 4));  // P * min_width == slices
  EXPECT_THROW(check_partition(std::vector<int>{3, 8}, 12, 4), InputError);
  EXPECT_THROW(check_partition(std::vector<int>{4, 8}, 11, 4), InputError);
  EXPECT_THROW(check_partition(std::vector<int>{}, 10, 0), InputError);
}

TEST(Partition, SweepTruncatesWithWidthsAfterEarlierMoves) {
  // b0 moves +4 to 12; b1 wants -4 to 12 but rank 1 must keep 4 slices after b0's move -> stays 16.
  const std::vector<int> b{8, 16};
  EXPECT_EQ(apply_moves(b, std::vector<long>{4, -4}, 24, 4), (std::vector<int>{12, 16}));
  // Moves beyond the domain edges are truncated at min_width from the edge.
  EXPECT_EQ(apply_moves(b, std::vector<long>{-100, 100}, 24, 4), (std::vector<int>{4, 20}));
  // With every width at the minimum nothing can move.
  EXPECT_EQ(apply_moves(std::vector<int>{4, 8}, std::vector<long>{3, -3}, 12, 4), (std::vector<int>{4, 8}));
}

TEST(Partition, MigrationAndRankSums) {
  EXPECT_EQ(migration(std::vector<int>{10, 20}, std::vector<int>{12, 17}), 5);
  const std::vector<double> work{1, 2, 3, 4};
  EXPECT_EQ(rank_sums(work, std::vector<int>{1, 3}), (std::vector<double>{1, 5, 4}));
}
