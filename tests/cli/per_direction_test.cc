#include "cli/per_direction.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace haptex::cli {
namespace {

using ::testing::HasSubstr;

template <typename F>
std::string ErrorOf(F parse) {
  try {
    parse();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(PerDirectionTest, OneValueServesBothDirections) {
  const auto values = ParsePerDirectionNumber("--delay-ms", "20");
  EXPECT_EQ(values.forward, 20.0);
  EXPECT_EQ(values.back, 20.0);
  EXPECT_FALSE(values.differ);
}

TEST(PerDirectionTest, TwoValuesAreForwardThenBack) {
  const auto values = ParsePerDirectionNumber("--loss", "0.01,1e-3");
  EXPECT_EQ(values.forward, 0.01);
  EXPECT_EQ(values.back, 0.001);
  EXPECT_TRUE(values.differ);
  EXPECT_EQ(DirectionFlagName("--loss", true, true), "--loss (back)");
  EXPECT_EQ(DirectionFlagName("--loss", true, false), "--loss (forward)");
  EXPECT_EQ(DirectionFlagName("--loss", false, true), "--loss");
}

TEST(PerDirectionTest, RefusesNanInfinityAndGarbageNamingTheFlag) {
  for (const char* bad : {"nan", "NaN", "inf", "-inf", "infinity", "1e999"}) {
    EXPECT_THAT(ErrorOf([&] { ParsePerDirectionNumber("--jitter-ms", bad); }), HasSubstr("--jitter-ms")) << bad;
  }
  EXPECT_THAT(ErrorOf([] { ParseFiniteNumber("--loss", "nan"); }), HasSubstr("not a finite number"));
  for (const char* bad : {"", "abc", "1.5x", " 1", "1,", ",1", "0x10", "1,2,3", "1;2"}) {
    EXPECT_THAT(ErrorOf([&] { ParsePerDirectionNumber("--loss", bad); }), HasSubstr("--loss")) << bad;
  }
  EXPECT_THAT(ErrorOf([] { ParsePerDirectionNumber("--loss", "1,2,3"); }), HasSubstr("FORWARD,BACK"));
}

TEST(PerDirectionTest, Words) {
  const auto one = ParsePerDirectionWord("--jitter-dist", "normal");
  EXPECT_EQ(one.forward, "normal");
  EXPECT_EQ(one.back, "normal");
  const auto two = ParsePerDirectionWord("--jitter-dist", "uniform,normal");
  EXPECT_EQ(two.forward, "uniform");
  EXPECT_EQ(two.back, "normal");
  EXPECT_THAT(ErrorOf([] { ParsePerDirectionWord("--jitter-dist", "normal,"); }), HasSubstr("empty"));
}

TEST(PerDirectionTest, NumberLists) {
  EXPECT_EQ(ParseNumberList("--burst-loss", "0.1,0.5", 2, 4), (std::vector<double>{0.1, 0.5}));
  EXPECT_EQ(ParseNumberList("--burst-loss", "0.1,0.5,0.9,0.01", 2, 4).size(), 4u);
  EXPECT_THAT(ErrorOf([] { ParseNumberList("--burst-loss", "0.1", 2, 4); }),
              HasSubstr("--burst-loss: expected 2 to 4 comma-separated numbers"));
  EXPECT_THAT(ErrorOf([] { ParseNumberList("--burst-loss", "0.1,nan", 2, 4); }), HasSubstr("finite"));
}

TEST(PerDirectionTest, SeedsOneOrTwo) {
  const auto one = ParsePerDirectionSeed("--seed", "7");
  EXPECT_EQ(one.forward, 7u);
  EXPECT_EQ(one.back, 8u);  // the directions must not draw the same
  const auto two = ParsePerDirectionSeed("--seed", "18446744073709551615,3");
  EXPECT_EQ(two.forward, 18446744073709551615u);
  EXPECT_EQ(two.back, 3u);
  for (const char* bad : {"-1", "1.5", "x", "18446744073709551616", ""}) {
    EXPECT_THAT(ErrorOf([&] { ParsePerDirectionSeed("--seed", bad); }), HasSubstr("--seed")) << bad;
  }
}

}  // namespace
}  // namespace haptex::cli
