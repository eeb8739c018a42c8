#pragma once
// Achieved delays for p50/p99/max without storing samples or allocating. Its own type rather than
// runtime::LatencyHistogram so that this core links nothing impure.

#include <array>
#include <cstdint>

namespace haptex::netsim {

/// Log-linear buckets over every non-negative int64: exact below 128 ns, then 64 buckets per
/// power of two (quantiles within 0.8 % of the true value). Max and min are exact.
class DelayHistogram final {
 public:
  static constexpr int kSubBucketBits = 6;
  static constexpr int kSubBuckets = 1 << kSubBucketBits;
  static constexpr int kBucketCount = kSubBuckets * 58;

  /// Negative delays (a clock that went backwards) are recorded as 0.
  void Record(std::int64_t delay_ns);

  std::uint64_t count() const { return count_; }
  std::int64_t min_ns() const { return count_ ? min_ns_ : 0; }
  std::int64_t max_ns() const { return max_ns_; }
  double mean_ns() const { return count_ ? sum_ns_ / static_cast<double>(count_) : 0.0; }
  /// The delay below or at which a fraction q (clamped to [0, 1]) of the samples lie; 0 when
  /// empty; the exact max for q = 1.
  double Quantile_ns(double q) const;

 private:
  static int BucketOf(std::uint64_t value_ns);
  static double BucketMiddle_ns(int bucket);

  std::array<std::uint64_t, kBucketCount> buckets_{};
  std::uint64_t count_ = 0;
  double sum_ns_ = 0.0;
  std::int64_t min_ns_ = 0;
  std::int64_t max_ns_ = 0;
};

}  // namespace haptex::netsim
