#pragma once
// A fixed-size log-linear histogram of durations (32 sub-buckets per power of two: <= 3.2 %
// relative error), for percentiles of loop periods, compute times and latencies without storing
// samples or allocating.

#include <array>
#include <cstdint>

namespace haptex::runtime {

class LatencyHistogram final {
 public:
  static constexpr int kSubBucketBits = 5;
  static constexpr int kSubBuckets = 1 << kSubBucketBits;
  static constexpr int kMaxShift = 40;  // values up to ~2^45 ns (about 10 hours)
  static constexpr int kBucketCount = kSubBuckets * (kMaxShift + 2);

  void Record(std::int64_t value_ns);
  void Reset();

  std::uint64_t count() const { return count_; }
  std::int64_t min_ns() const { return count_ ? min_ns_ : 0; }
  std::int64_t max_ns() const { return max_ns_; }
  double mean_ns() const { return count_ ? sum_ns_ / static_cast<double>(count_) : 0.0; }
  /// Value below which a fraction q (0..1) of the samples lie; 0 when empty. Exact at the max.
  double Percentile(double q) const;

 private:
  static int BucketOf(std::uint64_t value);
  static double BucketMid(int bucket);

  std::array<std::uint64_t, kBucketCount> buckets_{};
  std::uint64_t count_ = 0;
  double sum_ns_ = 0.0;  // double: huge samples must not overflow it
  std::int64_t min_ns_ = 0;
  std::int64_t max_ns_ = 0;
};

}  // namespace haptex::runtime
