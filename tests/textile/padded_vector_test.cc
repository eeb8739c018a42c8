#include "libs/textile/padded_vector.h"

#include <cstdint>

#include <gtest/gtest.h>

namespace haptex::textile {
namespace {

TEST(PaddedVectorTest, RowsAreFourApartAlignedWithZeroPads) {
  PaddedVector v(5);
  ASSERT_EQ(v.rows(), 5);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % 32, 0u);  // aligned 4-wide loads
  Eigen::VectorXd x(15);
  for (int i = 0; i < 15; ++i) x[i] = 1.0 + i;
  v.SetRows(x);
  for (int r = 0; r < 5; ++r) {
    EXPECT_EQ(v.row(r), x.segment<3>(3 * r)) << r;
    EXPECT_EQ(v.data()[4 * r + 3], 0.0) << r;
  }
  EXPECT_EQ(v.Rows(), x);
  // Sums over all entries, pads included, are the rows'.
  EXPECT_DOUBLE_EQ(v.vec().squaredNorm(), x.squaredNorm());
  EXPECT_DOUBLE_EQ(v.vec().sum(), x.sum());
}

TEST(PaddedVectorTest, AddRowsToAddsEachRow) {
  PaddedVector v(2);
  v.row(0) = Eigen::Vector3d(1, 2, 3);
  v.row(1) = Eigen::Vector3d(-4, 5, -6);
  Eigen::VectorXd y = Eigen::VectorXd::Constant(6, 10.0);
  v.AddRowsTo(&y);
  Eigen::VectorXd expected(6);
  expected << 11, 12, 13, 6, 15, 4;
  EXPECT_EQ(y, expected);
  v.SetZero();
  EXPECT_EQ(v.vec().cwiseAbs().maxCoeff(), 0.0);
}

TEST(PaddedVectorTest, EmptyHasNoRows) {
  PaddedVector v;
  EXPECT_EQ(v.rows(), 0);
  EXPECT_EQ(v.data(), nullptr);
  EXPECT_EQ(v.vec().size(), 0);
}

}  // namespace
}  // namespace haptex::textile
