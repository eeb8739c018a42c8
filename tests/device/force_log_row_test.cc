#include "libs/device/force_log_row.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <string_view>

namespace haptex::device {
namespace {

ForceLogRow SampleRow() {
  ForceLogRow row;
  row.time_ns = 1'234'567'890'123;
  row.commanded_D_N = {{{1.5, -2.25, 3.0}, {0.0, 0.125, -4.0}}};
  row.applied_D_N = {{{1.25, -2.0, 2.75}, {0.0, 0.0625, -3.5}}};
  row.host_timed_out = true;
  row.host_sequence = 4'000'000'000u;
  row.position_D_m = {{{0.0123456789, -0.0063, -0.1}, {0.0100000001, 0.0063, -0.1}}};
  return row;
}

TEST(ForceLogRowTest, WhatIsWrittenIsReadBack) {
  std::array<char, kForceLogLineBytes> line{};
  const std::size_t n = FormatForceLogRow(SampleRow(), line);
  ASSERT_GT(n, 0u);
  ASSERT_EQ(line[n - 1], '\n');
  ForceLogRow back;
  ASSERT_TRUE(ParseForceLogRow(std::string_view(line.data(), n), &back));
  const ForceLogRow row = SampleRow();
  EXPECT_EQ(back.time_ns, row.time_ns);
  EXPECT_EQ(back.commanded_D_N, row.commanded_D_N);
  EXPECT_EQ(back.applied_D_N, row.applied_D_N);
  EXPECT_EQ(back.host_timed_out, row.host_timed_out);
  EXPECT_EQ(back.host_sequence, row.host_sequence);
  for (std::size_t f = 0; f < 2; ++f) {
    for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(back.position_D_m[f][k], row.position_D_m[f][k], 1e-11);
  }
}

TEST(ForceLogRowTest, TheHeaderNamesEveryColumn) {
  EXPECT_EQ(std::count(kForceLogHeader.begin(), kForceLogHeader.end(), ',') + 1, kForceLogColumns);
  ForceLogRow row;
  EXPECT_FALSE(ParseForceLogRow(kForceLogHeader, &row));
}

TEST(ForceLogRowTest, LinesThatAreNotWholeRowsAreRefused) {
  std::array<char, kForceLogLineBytes> line{};
  const std::string whole(line.data(), FormatForceLogRow(SampleRow(), line));
  ForceLogRow row;
  for (std::size_t cut = 0; cut + 1 < whole.size(); ++cut) {
    // a writer killed mid-line can leave a prefix that parses as numbers: only a cut inside the
    // last number could pass, and that one keeps all 21 columns
    const std::string prefix = whole.substr(0, cut);
    if (std::count(prefix.begin(), prefix.end(), ',') == kForceLogColumns - 1) continue;
    EXPECT_FALSE(ParseForceLogRow(prefix, &row)) << prefix;
  }
  EXPECT_FALSE(ParseForceLogRow("1,2,3,4,5,6,7,8,9,10,11,12,13,0,17", &row)) << "the format without positions";
  EXPECT_FALSE(ParseForceLogRow(whole.substr(0, whole.size() - 1) + ",0", &row)) << "a column too many";
  std::string with_nan = whole;
  with_nan.replace(with_nan.find(',') + 1, 3, "nan");
  EXPECT_FALSE(ParseForceLogRow(with_nan, &row));
}

}  // namespace
}  // namespace haptex::device
