#include "libs/dual_layer/global_link_delay.h"

#include <algorithm>
#include <limits>

namespace haptex::dual_layer {

void GlobalLinkDelay::OnResultMerged(std::uint64_t steps_taken, std::uint64_t result_global_step) {
  // a result from a later step than global_sim's own (a restarted global_sim) is no measurement
  if (result_global_step > steps_taken) return;
  const std::uint64_t steps = steps_taken - result_global_step;
  recent_[static_cast<std::size_t>(next_)] =
      static_cast<std::uint32_t>(std::min<std::uint64_t>(steps, std::numeric_limits<std::uint32_t>::max()));
  next_ = (next_ + 1) % kWindow;
}

std::uint32_t GlobalLinkDelay::round_trip_steps() const { return *std::max_element(recent_.begin(), recent_.end()); }

double BorderVelocityWeight(std::uint32_t round_trip_steps) {
  return std::max(0.0, 1.0 - 0.25 * static_cast<double>(round_trip_steps));
}

}  // namespace haptex::dual_layer
