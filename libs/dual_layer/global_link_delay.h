#pragma once
// How late the global layer's border reaches the local layer, and how far the local layer may
// extrapolate it. The local layer moves a patch's border with the velocity global_sim sent; that
// velocity carries the border's catch-up with the merged interior. With the two layers apart by a
// network, the catch-up answers an interior a round trip old, and extrapolating it closes a delayed
// loop: a hanging strip pinched through a one-step (each way) link peaked at 1.8 x the
// single-layer force, a rubbed one at 4 x. Holding the border where it was cut (no extrapolation)
// is stable at every delay, at a small cost without delay (tests/dual_layer/dual_layer_delay_test.cc).

#include <array>
#include <cstdint>

namespace haptex::dual_layer {

/// The round trip of the global link in global steps, as global_sim sees it: when a result is
/// merged, the steps taken since the patch it was computed on was cut (0 when the result arrives
/// before the next step). Reports the largest of the last results, so a late one counts at once.
class GlobalLinkDelay {
 public:
  static constexpr int kWindow = 8;
  void OnResultMerged(std::uint64_t steps_taken, std::uint64_t result_global_step);
  std::uint32_t round_trip_steps() const;

 private:
  std::array<std::uint32_t, kWindow> recent_{};
  int next_ = 0;
};

/// The share of global_sim's border velocity the local layer extrapolates with: all of it when
/// results come back within the step, none from a round trip of 4 steps, linear between.
double BorderVelocityWeight(std::uint32_t round_trip_steps);

}  // namespace haptex::dual_layer
