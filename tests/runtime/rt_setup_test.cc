#include "libs/runtime/rt_setup.h"

#include <gtest/gtest.h>

#include <sched.h>

namespace haptex::runtime {
namespace {

TEST(RtSetupTest, AffinityPinsTheThread) {
  const RtSetupResult result = TrySetCpuAffinity({0});
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(sched_getcpu(), 0);
  // restore
  cpu_set_t all;
  CPU_ZERO(&all);
  for (int i = 0; i < CPU_SETSIZE; ++i) CPU_SET(i, &all);
  sched_setaffinity(0, sizeof(all), &all);
}

TEST(RtSetupTest, BadRequestsReportWhyAndDoNotThrow) {
  const RtSetupResult no_cpu = TrySetCpuAffinity({4096});
  EXPECT_FALSE(no_cpu.ok);
  EXPECT_NE(no_cpu.message.find("does not exist"), std::string::npos);
  EXPECT_FALSE(TrySetCpuAffinity({}).ok);
  const RtSetupResult bad_priority = TrySetFifoPriority(0);
  EXPECT_FALSE(bad_priority.ok);
  EXPECT_NE(bad_priority.message.find("1..99"), std::string::npos);
}

TEST(RtSetupTest, FifoEitherWorksOrSaysWhy) {
  const RtSetupResult result = TrySetFifoPriority(10);
  EXPECT_FALSE(result.message.empty());
  if (result.ok) {
    // go back to normal scheduling so the rest of the suite is unaffected
    sched_param param{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &param);
  } else {
    EXPECT_NE(result.message.find("refused"), std::string::npos);
  }
}

}  // namespace
}  // namespace haptex::runtime
