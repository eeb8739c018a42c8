#include "libs/runtime/latency_histogram.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "tests/support/allocation_counter.h"

namespace haptex::runtime {
namespace {

double ExactPercentile(std::vector<std::int64_t> v, double q) {
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return static_cast<double>(v[std::max<std::size_t>(rank, 1) - 1]);
}

TEST(LatencyHistogramTest, EmptyIsZero) {
  LatencyHistogram h;
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.Percentile(0.5), 0.0);
  EXPECT_EQ(h.max_ns(), 0);
}

TEST(LatencyHistogramTest, SmallValuesAreExact) {
  LatencyHistogram h;
  for (int v = 0; v < 20; ++v) h.Record(v);
  EXPECT_EQ(h.Percentile(0.5), 9.0);
  EXPECT_EQ(h.min_ns(), 0);
  EXPECT_EQ(h.max_ns(), 19);
  EXPECT_DOUBLE_EQ(h.mean_ns(), 9.5);
}

TEST(LatencyHistogramTest, PercentilesWithinBucketResolution) {
  std::mt19937 rng(7);
  std::lognormal_distribution<double> dist(std::log(200e3), 0.6);  // ~200 us with a long tail
  LatencyHistogram h;
  std::vector<std::int64_t> samples;
  for (int i = 0; i < 100000; ++i) {
    const auto v = static_cast<std::int64_t>(dist(rng));
    samples.push_back(v);
    h.Record(v);
  }
  for (double q : {0.5, 0.9, 0.99, 0.999}) {
    const double exact = ExactPercentile(samples, q);
    EXPECT_NEAR(h.Percentile(q), exact, exact / 32.0) << "q=" << q;
  }
  EXPECT_EQ(h.Percentile(1.0), static_cast<double>(*std::max_element(samples.begin(), samples.end())));
}

TEST(LatencyHistogramTest, NegativeAndHugeValuesAreClamped) {
  LatencyHistogram h;
  h.Record(-5);
  h.Record(std::int64_t{1} << 60);
  EXPECT_EQ(h.count(), 2u);
  EXPECT_EQ(h.min_ns(), 0);
  EXPECT_GT(h.Percentile(0.99), 1e15);
}

TEST(LatencyHistogramTest, RecordDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP();
  LatencyHistogram h;
  testing::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) h.Record(i * 997);
  (void)h.Percentile(0.99);
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::runtime
