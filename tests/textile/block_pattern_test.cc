#include "libs/textile/block_pattern.h"

#include <gtest/gtest.h>

namespace haptex::textile {
namespace {

TEST(BlockPatternTest, SymmetricSortedWithDiagonal) {
  const BlockPattern dut = BlockPattern::FromPairs(4, {{0, 2}, {2, 3}, {0, 2}});
  EXPECT_EQ(dut.rows(), 4);
  // Rows: 0 -> {0, 2}; 1 -> {1}; 2 -> {0, 2, 3}; 3 -> {2, 3}.
  EXPECT_EQ(dut.num_blocks(), 2 + 1 + 3 + 2);
  for (int r = 0; r < 4; ++r) {
    EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.diag_slot[static_cast<std::size_t>(r)])], r);
    for (int k = dut.row_start[static_cast<std::size_t>(r)] + 1;
         k < dut.row_start[static_cast<std::size_t>(r) + 1]; ++k) {
      EXPECT_LT(dut.cols[static_cast<std::size_t>(k) - 1], dut.cols[static_cast<std::size_t>(k)]);
    }
  }
  EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.Slot(2, 0))], 0);
  EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.Slot(0, 2))], 2);
}

TEST(BlockPatternDeathTest, MissingBlockIsABug) {
  const BlockPattern dut = BlockPattern::FromPairs(3, {{0, 1}});
  EXPECT_DEATH(dut.Slot(0, 2), "invariant");
}

}  // namespace
}  // namespace haptex::textile
