#include "libs/netsim/delay_histogram.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace haptex::netsim {

int DelayHistogram::BucketOf(std::uint64_t value_ns) {
  if (value_ns < 2 * kSubBuckets) return static_cast<int>(value_ns);
  const int msb = 63 - std::countl_zero(value_ns);
  const int shift = msb - kSubBucketBits;                // >= 1
  const auto top = static_cast<int>(value_ns >> shift);  // in [64, 127]
  return kSubBuckets * shift + top;
}

double DelayHistogram::BucketMiddle_ns(int bucket) {
  if (bucket < 2 * kSubBuckets) return bucket;
  const int shift = bucket / kSubBuckets - 1;
  const int top = bucket - kSubBuckets * shift;
  const double lower = std::ldexp(static_cast<double>(top), shift);
  return lower + 0.5 * (std::ldexp(1.0, shift) - 1.0);
}

void DelayHistogram::Record(std::int64_t delay_ns) {
  const std::int64_t value = std::max<std::int64_t>(delay_ns, 0);
  ++buckets_[static_cast<std::size_t>(BucketOf(static_cast<std::uint64_t>(value)))];
  if (count_ == 0 || value < min_ns_) min_ns_ = value;
  max_ns_ = std::max(max_ns_, value);
  sum_ns_ += static_cast<double>(value);
  ++count_;
}

double DelayHistogram::Quantile_ns(double q) const {
  if (count_ == 0) return 0.0;
  q = std::isnan(q) ? 0.0 : std::clamp(q, 0.0, 1.0);
  const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_))));
  if (rank >= count_) return static_cast<double>(max_ns_);
  std::uint64_t seen = 0;
  for (int b = 0; b < kBucketCount; ++b) {
    seen += buckets_[static_cast<std::size_t>(b)];
    if (seen >= rank) {
      return std::clamp(BucketMiddle_ns(b), static_cast<double>(min_ns_), static_cast<double>(max_ns_));
    }
  }
  return static_cast<double>(max_ns_);
}

}  // namespace haptex::netsim
