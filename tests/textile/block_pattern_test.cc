#include "libs/textile/block_pattern.h"

#include <bit>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "libs/base/cpu_features.h"

namespace haptex::textile {
namespace {

// Random blocks for every slot of `pattern` (the scalar ones a multiple of I) and the values of
// the scalar blocks in split's order.
void RandomBlocks(const BlockPattern& pattern, const SplitRows& split, const std::vector<unsigned char>& is_scalar,
                  std::mt19937* rng, std::vector<Eigen::Matrix3d>* blocks, std::vector<double>* scalars) {
  std::normal_distribution<double> normal;
  blocks->assign(pattern.cols.size(), Eigen::Matrix3d::Zero());
  for (std::size_t k = 0; k < blocks->size(); ++k) {
    for (int i = 0; i < 9; ++i) (*blocks)[k](i / 3, i % 3) = normal(*rng);
    if (is_scalar[k]) (*blocks)[k] = (*blocks)[k](0, 0) * Eigen::Matrix3d::Identity();
  }
  scalars->clear();
  for (int slot : split.scalar_slot) scalars->push_back((*blocks)[static_cast<std::size_t>(slot)](0, 0));
}

TEST(BlockPatternTest, SymmetricSortedWithDiagonal) {
  const BlockPattern dut = BlockPattern::FromPairs(4, {{0, 2}, {2, 3}, {0, 2}});
  EXPECT_EQ(dut.rows(), 4);
  // Rows: 0 -> {0, 2}; 1 -> {1}; 2 -> {0, 2, 3}; 3 -> {2, 3}.
  EXPECT_EQ(dut.num_blocks(), 2 + 1 + 3 + 2);
  for (int r = 0; r < 4; ++r) {
    EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.diag_slot[static_cast<std::size_t>(r)])], r);
    for (int k = dut.row_start[static_cast<std::size_t>(r)] + 1; k < dut.row_start[static_cast<std::size_t>(r) + 1];
         ++k) {
      EXPECT_LT(dut.cols[static_cast<std::size_t>(k) - 1], dut.cols[static_cast<std::size_t>(k)]);
    }
  }
  EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.Slot(2, 0))], 0);
  EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.Slot(0, 2))], 2);
}

TEST(BlockPatternTest, MovedBlocksGoToTheRowEndsAndTheSplitProductAgrees) {
  // Rows: 0 -> {0, 1, 2}; 1 -> {0, 1, 3}; 2 -> {0, 2, 3}; 3 -> {1, 2, 3}. Blocks (0, 2), (2, 0),
  // (1, 3), (3, 1) are scalar.
  BlockPattern dut = BlockPattern::FromPairs(4, {{0, 1}, {0, 2}, {1, 3}, {2, 3}});
  const auto scalar = [&dut](int r, int k) {
    const int c = dut.cols[static_cast<std::size_t>(k)];
    return (r == 0 && c == 2) || (r == 2 && c == 0) || (r == 1 && c == 3) || (r == 3 && c == 1);
  };
  const auto marks = [&dut, &scalar] {
    std::vector<unsigned char> m(dut.cols.size(), 0);
    for (int r = 0; r < dut.rows(); ++r) {
      const auto row = static_cast<std::size_t>(r);
      for (int k = dut.row_start[row]; k < dut.row_start[row + 1]; ++k) {
        m[static_cast<std::size_t>(k)] = scalar(r, k) ? 1 : 0;
      }
    }
    return m;
  };
  dut.MoveToRowEnds(marks());
  // Row 0 is now {0, 1, 2}: the scalar block last; row 2 is {2, 3, 0}.
  EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.row_start[2])], 2);
  EXPECT_EQ(dut.Slot(2, 0), dut.row_start[3] - 1);
  for (int r = 0; r < 4; ++r) {
    EXPECT_EQ(dut.cols[static_cast<std::size_t>(dut.diag_slot[static_cast<std::size_t>(r)])], r);
  }
  const std::vector<unsigned char> is_scalar = marks();
  const SplitRows split = SplitRows::FromPattern(dut, is_scalar);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Matrix3d> blocks;
  std::vector<double> scalars;
  RandomBlocks(dut, split, is_scalar, &rng, &blocks, &scalars);
  Eigen::VectorXd x(12), y_ref(12), y(12);
  for (int i = 0; i < 12; ++i) x[i] = normal(rng);
  const auto active = [](int r) { return r != 1; };
  MultiplyBlockRows(dut, blocks, active, x, &y_ref);
  const double xy = MultiplySplitRows(split, blocks, scalars, active, x, &y);
  EXPECT_LT((y - y_ref).norm(), 1e-12 * y_ref.norm());
  EXPECT_EQ(y.segment<3>(3).norm(), 0.0);
  EXPECT_NEAR(xy, x.dot(y_ref), 1e-12 * y_ref.norm() * x.norm());

  // The AVX and the portable kernel give the same bits (rows 2..3 reach x's last row).
  if (base::CpuHasAvx()) {
    Eigen::VectorXd y_avx = Eigen::VectorXd::Zero(12), y_portable = Eigen::VectorXd::Zero(12);
    const double xy_avx =
        internal::MultiplySplitRowRange(split, blocks.data(), scalars.data(), x.data(), y_avx.data(), 0, 4, true);
    const double xy_portable =
        internal::MultiplySplitRowRange(split, blocks.data(), scalars.data(), x.data(), y_portable.data(), 0, 4, false);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(xy_avx), std::bit_cast<std::uint64_t>(xy_portable));
    EXPECT_EQ(std::memcmp(y_avx.data(), y_portable.data(), 12 * sizeof(double)), 0);
  }
}

// On a grid's pattern (3 x 3 neighbourhoods general, bending couplings two apart scalar) every
// row shape the kernels have code for (9 general and 4 scalar blocks, fixed-trip; fewer, looped)
// gives the AVX kernel the portable one's bits, and both the block product's sums.
TEST(BlockPatternTest, GridRowShapesGiveThePortableBits) {
  constexpr int kSide = 7, kRows = kSide * kSide;
  std::vector<std::pair<int, int>> pairs;
  std::vector<std::pair<int, int>> scalar_pairs;
  for (int i = 0; i < kSide; ++i) {
    for (int j = 0; j < kSide; ++j) {
      const int r = i * kSide + j;
      for (int di = -1; di <= 1; ++di) {
        for (int dj = -1; dj <= 1; ++dj) {
          const bool inside = i + di >= 0 && i + di < kSide && j + dj >= 0 && j + dj < kSide;
          if (inside) pairs.push_back({r, r + di * kSide + dj});
        }
      }
      if (i + 2 < kSide) scalar_pairs.push_back({r, r + 2 * kSide});
      if (j + 2 < kSide) scalar_pairs.push_back({r, r + 2});
    }
  }
  std::vector<std::pair<int, int>> all = pairs;
  all.insert(all.end(), scalar_pairs.begin(), scalar_pairs.end());
  BlockPattern dut = BlockPattern::FromPairs(kRows, all);
  const auto marks = [&] {
    std::vector<unsigned char> m(dut.cols.size(), 0);
    for (int r = 0; r < kRows; ++r) {
      for (int k = dut.row_start[static_cast<std::size_t>(r)]; k < dut.row_start[static_cast<std::size_t>(r) + 1];
           ++k) {
        const int c = dut.cols[static_cast<std::size_t>(k)];
        const int di = c / kSide - r / kSide, dj = c % kSide - r % kSide;
        m[static_cast<std::size_t>(k)] = (std::abs(di) == 2 && dj == 0) || (di == 0 && std::abs(dj) == 2) ? 1 : 0;
      }
    }
    return m;
  };
  dut.MoveToRowEnds(marks());
  const std::vector<unsigned char> is_scalar = marks();
  const SplitRows split = SplitRows::FromPattern(dut, is_scalar);
  // The shapes: 9 and 4 (interior), fewer on the sides.
  int interior = 0;
  for (int r = 0; r < kRows; ++r) {
    const auto row = static_cast<std::size_t>(r);
    const int general = split.general_start[row + 1] - split.general_start[row];
    const int scalar = split.scalar_start[row + 1] - split.scalar_start[row];
    interior += general == 9 && scalar == 4 ? 1 : 0;
  }
  EXPECT_EQ(interior, (kSide - 4) * (kSide - 4));
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  std::vector<Eigen::Matrix3d> blocks;
  std::vector<double> scalars;
  RandomBlocks(dut, split, is_scalar, &rng, &blocks, &scalars);
  Eigen::VectorXd x(3 * kRows), y_ref(3 * kRows), y(3 * kRows);
  for (int i = 0; i < 3 * kRows; ++i) x[i] = normal(rng);
  const auto active = [](int r) { return r % 5 != 2; };
  MultiplyBlockRows(dut, blocks, active, x, &y_ref);
  const double xy = MultiplySplitRows(split, blocks, scalars, active, x, &y);
  EXPECT_LT((y - y_ref).norm(), 1e-12 * y_ref.norm());
  EXPECT_NEAR(xy, x.dot(y_ref), 1e-12 * y_ref.norm() * x.norm());
  if (base::CpuHasAvx()) {
    Eigen::VectorXd y_avx = Eigen::VectorXd::Zero(3 * kRows), y_portable = y_avx;
    const double xy_avx =
        internal::MultiplySplitRowRange(split, blocks.data(), scalars.data(), x.data(), y_avx.data(), 0, kRows, true);
    const double xy_portable = internal::MultiplySplitRowRange(split, blocks.data(), scalars.data(), x.data(),
                                                               y_portable.data(), 0, kRows, false);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(xy_avx), std::bit_cast<std::uint64_t>(xy_portable));
    EXPECT_EQ(std::memcmp(y_avx.data(), y_portable.data(), 3 * kRows * sizeof(double)), 0);
  }
}

TEST(BlockPatternDeathTest, MissingBlockIsABug) {
  const BlockPattern dut = BlockPattern::FromPairs(3, {{0, 1}});
  EXPECT_DEATH(dut.Slot(0, 2), "invariant");
}

}  // namespace
}  // namespace haptex::textile
