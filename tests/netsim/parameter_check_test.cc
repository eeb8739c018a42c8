#include "libs/netsim/parameter_check.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace haptex::netsim {
namespace {

using ::testing::HasSubstr;

std::string MessageOf(void (*check)(std::string_view, double), double value) {
  try {
    check("--knob", value);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ParameterCheckTest, FiniteRefusesNanAndInfinityNamingTheParameter) {
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  EXPECT_NO_THROW(CheckFinite("x", -1e300));
  EXPECT_THAT(MessageOf(CheckFinite, kNan), HasSubstr("--knob must be a finite number, got nan"));
  EXPECT_THAT(MessageOf(CheckFinite, kInf), HasSubstr("--knob"));
  EXPECT_THAT(MessageOf(CheckFinite, -kInf), HasSubstr("-inf"));
}

TEST(ParameterCheckTest, ProbabilityIsWithinZeroAndOne) {
  EXPECT_NO_THROW(CheckProbability("p", 0.0));
  EXPECT_NO_THROW(CheckProbability("p", 1.0));
  EXPECT_THAT(MessageOf(CheckProbability, 1.5), HasSubstr("--knob must be a probability within [0, 1], got 1.5"));
  EXPECT_THAT(MessageOf(CheckProbability, -0.1), HasSubstr("got -0.1"));
  EXPECT_THAT(MessageOf(CheckProbability, std::numeric_limits<double>::quiet_NaN()), HasSubstr("finite"));
}

TEST(ParameterCheckTest, RangeAndWholeNumbers) {
  EXPECT_NO_THROW(CheckRange("x", 5.0, 0.0, 5.0));
  try {
    CheckRange("delay_ms", -1.0, 0.0, 60000.0);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("delay_ms must be within [0, 60000], got -1"));
  }
  EXPECT_NO_THROW(CheckWholeNumber("n", 7.0, 1.0, 10.0));
  EXPECT_THROW(CheckWholeNumber("n", 7.5, 1.0, 10.0), std::invalid_argument);
  EXPECT_THROW(CheckWholeNumber("n", 0.0, 1.0, 10.0), std::invalid_argument);
}

}  // namespace
}  // namespace haptex::netsim
