#include "libs/device/latency_tracker.h"

#include <algorithm>
#include <cmath>

namespace haptex::device {

void LatencyTracker::Record(double latency_s) {
  if (!(latency_s >= 0.0) || !std::isfinite(latency_s)) {
    ++invalid_;
    return;
  }
  ++count_;
  max_s_ = std::max(max_s_, latency_s);
  const double bin = std::floor(latency_s / bin_width_s_);
  if (bin >= static_cast<double>(kBinCount)) {
    ++overflow_;
  } else {
    ++bins_[static_cast<std::size_t>(bin)];
  }
}

double LatencyTracker::Percentile(double p) const {
  if (count_ == 0) return 0.0;
  p = std::clamp(p, 0.0, 1.0);
  // rank of the sample that must be covered (1-based)
  const auto rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(p * static_cast<double>(count_))));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBinCount; ++i) {
    seen += bins_[i];
    if (seen >= rank) return std::min(static_cast<double>(i + 1) * bin_width_s_, max_s_);
  }
  return max_s_;
}

void LatencyTracker::Reset() {
  bins_.fill(0);
  overflow_ = 0;
  count_ = 0;
  invalid_ = 0;
  max_s_ = 0.0;
}

}  // namespace haptex::device
