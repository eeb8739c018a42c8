// HAPTEX_DEMAND: nothing when the condition holds, an abort naming file:line and the condition
// when it does not, in every build type.
#include "libs/base/demand.h"

#include <gtest/gtest.h>

#include <csignal>

namespace haptex::base {
namespace {

int Checked(int value) {
  HAPTEX_DEMAND(value >= 0);
  return value;
}

TEST(DemandTest, PassesWhenTheConditionHolds) { EXPECT_EQ(Checked(3), 3); }

TEST(DemandTest, EvaluatesTheConditionOnce) {
  int calls = 0;
  HAPTEX_DEMAND(++calls == 1);
  EXPECT_EQ(calls, 1);
}

TEST(DemandDeathTest, AbortsNamingFileLineAndCondition) {
  EXPECT_DEATH(Checked(-1), "demand_test\\.cc:[0-9]+: haptex invariant failed: value >= 0");
}

TEST(DemandDeathTest, AbortsWithSigabrt) {
  EXPECT_EXIT(Checked(-1), ::testing::KilledBySignal(SIGABRT), "invariant failed");
}

}  // namespace
}  // namespace haptex::base
