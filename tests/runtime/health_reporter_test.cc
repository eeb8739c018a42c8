#include "libs/runtime/health_reporter.h"

#include <gtest/gtest.h>

#include <string_view>

#include "tests/support/allocation_counter.h"

namespace haptex::runtime {
namespace {

TEST(HealthReporterTest, BuildsHealthFromRegisteredSources) {
  LoopStats loop;
  loop.name = "haptic";
  loop.target_rate_hz = 1000;
  loop.ticks = 10;
  loop.overruns = 2;
  for (int i = 0; i < 10; ++i) loop.period.Record(1000000);
  LatencyHistogram latency;
  latency.Record(1500000);
  HealthReporter reporter("local_contact");
  reporter.AddLoop(&loop);
  reporter.AddLatency("motion_to_force", &latency);
  const auto drops = reporter.AddCounter("dropped_bad_mac");
  reporter.SetCounter(drops, 7);
  reporter.SetState(v1::Health::STATE_READY);

  const v1::Health& h = reporter.Build(3.5);
  EXPECT_EQ(h.service(), "local_contact");
  EXPECT_EQ(h.state(), v1::Health::STATE_READY);
  EXPECT_DOUBLE_EQ(h.uptime_s(), 3.5);
  EXPECT_GT(h.pid(), 0u);
  ASSERT_EQ(h.loops_size(), 1);
  EXPECT_EQ(h.loops(0).name(), "haptic");
  EXPECT_EQ(h.loops(0).overruns(), 2u);
  EXPECT_NEAR(h.loops(0).period_p50_us(), 1000.0, 1000.0 / 32);
  ASSERT_EQ(h.latencies_size(), 1);
  EXPECT_NEAR(h.latencies(0).max_us(), 1500.0, 1e-9);
  ASSERT_EQ(h.counters_size(), 1);
  EXPECT_EQ(h.counters(0).name(), "dropped_bad_mac");
  EXPECT_EQ(h.counters(0).value(), 7u);
}

TEST(HealthReporterTest, OneCounterPerReasonNamedByPrefixAndReason) {
  enum class Reason { kNone, kTorn, kLate, kCount };
  HealthReporter reporter("svc");
  const auto ids = reporter.AddCounterPerReason<Reason, 3>(
      "frames_", [](Reason r) -> std::string_view { return r == Reason::kTorn ? "torn" : "late"; });
  reporter.SetCounter(ids[2], 7);
  const v1::Health& h = reporter.Build(0.0);
  ASSERT_EQ(h.counters_size(), 2);
  EXPECT_EQ(h.counters(0).name(), "frames_torn");
  EXPECT_EQ(h.counters(1).name(), "frames_late");
  EXPECT_EQ(h.counters(1).value(), 7u);
}

TEST(HealthReporterTest, RebuildDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP();
  LoopStats loop;
  loop.name = "bridge";
  HealthReporter reporter("device_bridge");
  reporter.AddLoop(&loop);
  const auto c = reporter.AddCounter("watchdog_trips");
  reporter.Build(0.0);
  testing::AllocationCounter counter;
  for (int i = 0; i < 100; ++i) {
    loop.period.Record(200000 + i);
    reporter.SetCounter(c, static_cast<std::uint64_t>(i));
    reporter.Build(i * 0.01);
  }
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::runtime
