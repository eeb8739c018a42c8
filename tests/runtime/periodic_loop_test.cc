#include "libs/runtime/periodic_loop.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "tests/support/allocation_counter.h"

namespace haptex::runtime {
namespace {

// Timing is not asserted (shared, noisy machine); ordering, accounting and bounds are.

TEST(PeriodicLoopTest, RejectsBadRates) {
  EXPECT_THROW(PeriodicLoop("x", 0.0), std::invalid_argument);
  EXPECT_THROW(PeriodicLoop("x", -5.0), std::invalid_argument);
  EXPECT_THROW(PeriodicLoop("x", 1e6), std::invalid_argument);
  EXPECT_THROW(PeriodicLoop("x", std::nan("")), std::invalid_argument);
}

TEST(PeriodicLoopTest, TicksInOrderWithFixedDtAndNeverEarly) {
  PeriodicLoop loop("test", 1000.0);
  std::vector<TickInfo> ticks;
  ticks.reserve(100);
  loop.Run([&](const TickInfo& info) { ticks.push_back(info); }, [&] { return ticks.size() >= 50; });
  ASSERT_EQ(ticks.size(), 50u);
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    EXPECT_EQ(ticks[i].tick, i);
    EXPECT_DOUBLE_EQ(ticks[i].dt_s, 0.001);
    EXPECT_GE(ticks[i].now_ns, ticks[i].deadline_ns);  // never runs before its deadline
    if (i > 0) {
      EXPECT_GT(ticks[i].deadline_ns, ticks[i - 1].deadline_ns);
      EXPECT_GT(ticks[i].measured_period_ns, 0);
      // deadlines are absolute: a multiple of the period apart, never drifting
      EXPECT_EQ((ticks[i].deadline_ns - ticks[0].deadline_ns) % loop.period_ns(), 0);
    }
  }
  EXPECT_EQ(loop.stats().ticks, 50u);
  EXPECT_EQ(loop.stats().period.count(), 49u);
  EXPECT_EQ(loop.stats().compute.count(), 50u);
}

TEST(PeriodicLoopTest, SlowTickIsCountedAsOverrunAndMissedCyclesAreSkipped) {
  PeriodicLoop loop("slow", 500.0);  // 2 ms period
  std::vector<TickInfo> ticks;
  ticks.reserve(100);
  loop.Run(
      [&](const TickInfo& info) {
        ticks.push_back(info);
        if (info.tick == 5) std::this_thread::sleep_for(std::chrono::milliseconds(9));
      },
      [&] { return ticks.size() >= 12; });
  // the 9 ms tick makes the next one at least 3 full periods late
  EXPECT_GE(loop.stats().overruns, 3u);
  EXPECT_GE(ticks[6].skipped, 3u);
  // skipped cycles are not run back to back: the tick after the slow one starts within a period
  // of its (moved) deadline
  EXPECT_LT(ticks[6].now_ns - ticks[6].deadline_ns, loop.period_ns());
  std::uint64_t skipped = 0;
  for (const auto& t : ticks) skipped += t.skipped;
  EXPECT_EQ(skipped, loop.stats().overruns);
}

TEST(PeriodicLoopTest, StopIsCheckedBeforeEveryTick) {
  PeriodicLoop loop("stop", 1000.0);
  int ticks = 0;
  loop.Run([&](const TickInfo&) { ++ticks; }, [] { return true; });
  EXPECT_EQ(ticks, 0);
}

TEST(PeriodicLoopTest, LoopMachineryDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP();
  PeriodicLoop loop("alloc", 2000.0);
  int ticks = 0;
  testing::AllocationCounter counter;
  loop.Run([&](const TickInfo&) { ++ticks; }, [&] { return ticks >= 20; });
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::runtime
