#include "libs/device/latency_tracker.h"

#include <gtest/gtest.h>

#include <limits>
#include <memory>

#include "tests/support/allocation_counter.h"

namespace haptex::device {
namespace {

TEST(LatencyTrackerTest, EmptyReportsZero) {
  LatencyTracker dut;
  EXPECT_EQ(dut.count(), 0u);
  EXPECT_EQ(dut.p50_s(), 0.0);
  EXPECT_EQ(dut.max_s(), 0.0);
}

TEST(LatencyTrackerTest, PercentilesOfAKnownDistribution) {
  auto dut = std::make_unique<LatencyTracker>();
  // 1, 2, ..., 100 us (recorded at the middle of each bin)
  for (int i = 1; i <= 100; ++i) dut->Record((i - 0.5) * 1e-6);
  EXPECT_EQ(dut->count(), 100u);
  EXPECT_NEAR(dut->p50_s(), 50e-6, 1e-12);
  EXPECT_NEAR(dut->p99_s(), 99e-6, 1e-12);
  EXPECT_NEAR(dut->Percentile(1.0), 99.5e-6, 1e-12);  // capped by the exact max
  EXPECT_NEAR(dut->max_s(), 99.5e-6, 1e-15);
}

TEST(LatencyTrackerTest, OverflowKeepsExactMax) {
  auto dut = std::make_unique<LatencyTracker>();
  for (int i = 0; i < 98; ++i) dut->Record(100.5e-6);
  dut->Record(0.05);
  dut->Record(0.25);
  EXPECT_EQ(dut->overflow(), 2u);
  EXPECT_NEAR(dut->p50_s(), 101e-6, 1e-12);
  EXPECT_EQ(dut->max_s(), 0.25);
  EXPECT_EQ(dut->Percentile(1.0), 0.25);
}

TEST(LatencyTrackerTest, InvalidSamplesAreCountedNotRecorded) {
  auto dut = std::make_unique<LatencyTracker>();
  dut->Record(-1e-6);
  dut->Record(std::numeric_limits<double>::quiet_NaN());
  dut->Record(std::numeric_limits<double>::infinity());
  EXPECT_EQ(dut->invalid(), 3u);
  EXPECT_EQ(dut->count(), 0u);
  dut->Record(3e-6);
  dut->Reset();
  EXPECT_EQ(dut->count(), 0u);
  EXPECT_EQ(dut->invalid(), 0u);
}

TEST(LatencyTrackerTest, RecordAndQueryDoNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  auto dut = std::make_unique<LatencyTracker>();
  testing::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) dut->Record(i * 1e-6);
  const double p99 = dut->p99_s();
  EXPECT_EQ(counter.count(), 0);
  EXPECT_GT(p99, 0.0);
}

}  // namespace
}  // namespace haptex::device
