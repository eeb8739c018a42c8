#include "libs/runtime/rt_setup.h"

#include <gtest/gtest.h>

#include <sched.h>

namespace haptex::runtime {
namespace {

int FirstAllowedCpu(const cpu_set_t& set) {
  for (int i = 0; i < CPU_SETSIZE; ++i) {
    if (CPU_ISSET(i, &set)) return i;
  }
  return 0;
}

TEST(RtSetupTest, AffinityPinsTheThread) {
  cpu_set_t original;
  ASSERT_EQ(sched_getaffinity(0, sizeof(original), &original), 0);
  const int cpu = FirstAllowedCpu(original);
  const RtSetupResult result = TrySetCpuAffinity({cpu});
  ASSERT_TRUE(result.ok) << result.message;
  EXPECT_EQ(sched_getcpu(), cpu);
  sched_setaffinity(0, sizeof(original), &original);
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
