#pragma once
// Fixed-histogram latency statistics (p50/p99/max) that never allocate.

#include <array>
#include <cstddef>
#include <cstdint>

namespace haptex::device {

/// Records latencies into kBinCount bins of `bin_width_s` (1 us: 0 to 10 ms) plus an overflow bin;
/// max is exact. Percentiles are reported as the upper edge of their bin (so they over-estimate by
/// less than a bin), or as the exact max when they fall into the overflow bin.
class LatencyTracker {
 public:
  static constexpr double kDefaultBinWidth_s = 1e-6;
  static constexpr std::size_t kBinCount = 10000;

  explicit LatencyTracker(double bin_width_s = kDefaultBinWidth_s) : bin_width_s_(bin_width_s) {}

  /// Adds one sample. Negative or non-finite samples are counted in invalid() and not recorded.
  void Record(double latency_s);
  /// Smallest latency L such that at least fraction `p` (in [0, 1]) of samples are <= L. 0 if
  /// there are no samples.
  double Percentile(double p) const;
  double p50_s() const { return Percentile(0.50); }
  double p99_s() const { return Percentile(0.99); }
  double max_s() const { return max_s_; }
  std::uint64_t count() const { return count_; }
  std::uint64_t invalid() const { return invalid_; }
  std::uint64_t overflow() const { return overflow_; }
  void Reset();

 private:
  double bin_width_s_;
  std::array<std::uint32_t, kBinCount> bins_{};
  std::uint64_t overflow_ = 0;
  std::uint64_t count_ = 0;
  std::uint64_t invalid_ = 0;
  double max_s_ = 0.0;
};

}  // namespace haptex::device
