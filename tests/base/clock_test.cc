// The one monotonic clock: never goes back, counts nanoseconds, and is CLOCK_MONOTONIC (the clock
// other processes on this machine, and clock_nanosleep's absolute deadlines, use).
#include "libs/base/clock.h"

#include <gtest/gtest.h>
#include <time.h>

#include <chrono>
#include <cstdint>
#include <thread>

namespace haptex::base {
namespace {

std::int64_t ClockMonotonicNs() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return std::int64_t{t.tv_sec} * 1000000000 + t.tv_nsec;
}

TEST(ClockTest, NeverGoesBack) {
  std::int64_t last = SteadyNowNs();
  for (int i = 0; i < 100000; ++i) {
    const std::int64_t now = SteadyNowNs();
    ASSERT_GE(now, last);
    last = now;
  }
}

TEST(ClockTest, CountsNanoseconds) {
  const std::int64_t start = SteadyNowNs();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const std::int64_t elapsed = SteadyNowNs() - start;
  EXPECT_GE(elapsed, 20'000'000);
  EXPECT_LT(elapsed, 20'000'000'000);  // a very loaded host, not a unit error
}

TEST(ClockTest, IsClockMonotonic) {
  const std::int64_t before = ClockMonotonicNs();
  const std::int64_t now = SteadyNowNs();
  const std::int64_t after = ClockMonotonicNs();
  EXPECT_LE(before, now);
  EXPECT_LE(now, after);
}

}  // namespace
}  // namespace haptex::base
