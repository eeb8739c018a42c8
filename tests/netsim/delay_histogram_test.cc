#include "libs/netsim/delay_histogram.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <memory>

#include "tests/support/allocation_counter.h"

namespace haptex::netsim {
namespace {

TEST(DelayHistogramTest, EmptyIsZero) {
  const auto dut = std::make_unique<DelayHistogram>();
  EXPECT_EQ(dut->count(), 0u);
  EXPECT_EQ(dut->Quantile_ns(0.5), 0.0);
  EXPECT_EQ(dut->max_ns(), 0);
  EXPECT_EQ(dut->mean_ns(), 0.0);
}

TEST(DelayHistogramTest, SmallValuesAreExact) {
  const auto dut = std::make_unique<DelayHistogram>();
  for (int v = 1; v <= 100; ++v) dut->Record(v);
  EXPECT_EQ(dut->Quantile_ns(0.5), 50.0);
  EXPECT_EQ(dut->Quantile_ns(0.99), 99.0);
  EXPECT_EQ(dut->Quantile_ns(1.0), 100.0);
  EXPECT_EQ(dut->min_ns(), 1);
  EXPECT_DOUBLE_EQ(dut->mean_ns(), 50.5);
}

TEST(DelayHistogramTest, QuantilesOfMillisecondDelaysWithinOnePercent) {
  const auto dut = std::make_unique<DelayHistogram>();
  // 20.000 ms to 29.999 ms in 1 us steps: p50 = 25 ms, p99 = 29.9 ms
  for (std::int64_t us = 0; us < 10000; ++us) dut->Record(20'000'000 + us * 1000);
  EXPECT_NEAR(dut->Quantile_ns(0.50), 25e6, 0.01 * 25e6);
  EXPECT_NEAR(dut->Quantile_ns(0.99), 29.9e6, 0.01 * 29.9e6);
  EXPECT_EQ(dut->max_ns(), 29'999'000);
  EXPECT_EQ(dut->Quantile_ns(1.0), 29'999'000.0);
}

TEST(DelayHistogramTest, ExtremesAreRecordedNotLost) {
  const auto dut = std::make_unique<DelayHistogram>();
  dut->Record(-5);  // a clock that went backwards
  dut->Record(std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(dut->count(), 2u);
  EXPECT_EQ(dut->min_ns(), 0);
  EXPECT_EQ(dut->max_ns(), std::numeric_limits<std::int64_t>::max());
}

TEST(DelayHistogramTest, RecordAndQuantilesDoNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP() << "allocation counting unavailable";
  const auto dut = std::make_unique<DelayHistogram>();
  testing::AllocationCounter counter;
  for (int i = 0; i < 10000; ++i) dut->Record(i * 997);
  const double p99 = dut->Quantile_ns(0.99);
  EXPECT_EQ(counter.count(), 0);
  EXPECT_GT(p99, 0.0);
}

}  // namespace
}  // namespace haptex::netsim
