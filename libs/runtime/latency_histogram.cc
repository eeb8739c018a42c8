#include "libs/runtime/latency_histogram.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace haptex::runtime {

int LatencyHistogram::BucketOf(std::uint64_t value) {
  if (value < static_cast<std::uint64_t>(kSubBuckets)) return static_cast<int>(value);
  const int msb = 63 - std::countl_zero(value);
  int shift = msb - kSubBucketBits;
  if (shift > kMaxShift) return kBucketCount - 1;
  const auto top = static_cast<int>(value >> shift);  // in [32, 63]
  return kSubBuckets * shift + top;
}

double LatencyHistogram::BucketMid(int bucket) {
  if (bucket < 2 * kSubBuckets) return bucket;
  const int shift = bucket / kSubBuckets - 1;
  const int top = bucket - kSubBuckets * shift;
  const double lower = std::ldexp(static_cast<double>(top), shift);
  const double width = std::ldexp(1.0, shift);
  return lower + 0.5 * (width - 1.0);
}

void LatencyHistogram::Record(std::int64_t value_ns) {
  const std::int64_t value = std::max<std::int64_t>(value_ns, 0);
  ++buckets_[static_cast<std::size_t>(BucketOf(static_cast<std::uint64_t>(value)))];
  if (count_ == 0 || value < min_ns_) min_ns_ = value;
  max_ns_ = std::max(max_ns_, value);
  sum_ns_ += static_cast<double>(value);
  ++count_;
}

void LatencyHistogram::Reset() { *this = LatencyHistogram{}; }

double LatencyHistogram::Percentile(double q) const {
  if (count_ == 0) return 0.0;
  q = std::clamp(q, 0.0, 1.0);
  const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_))));
  if (rank >= count_) return static_cast<double>(max_ns_);
  std::uint64_t seen = 0;
  for (int b = 0; b < kBucketCount; ++b) {
    seen += buckets_[static_cast<std::size_t>(b)];
    if (seen >= rank) {
      return std::clamp(BucketMid(b), static_cast<double>(min_ns_), static_cast<double>(max_ns_));
    }
  }
  return static_cast<double>(max_ns_);
}

}  // namespace haptex::runtime
