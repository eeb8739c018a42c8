#pragma once
// The tactile service's work per display tick, apart from sockets: newest TouchTrace per finger
// in, one RenderStep per finger, a PinFrame message out. Allocates nothing once warmed up.

#include <array>
#include <cstdint>
#include <memory>

#include "haptex/v1/pin_frame.pb.h"
#include "haptex/v1/touch_trace.pb.h"
#include "libs/tactile/pin_renderer.h"

namespace haptex::tactile_service {

class TactileLoop final {
 public:
  /// `stale_after_s`: a finger whose last TouchTrace is older is silent.
  TactileLoop(std::unique_ptr<tactile::RendererModel> model, double stale_after_s = 0.05);

  /// Takes the fingers of a TouchTrace received at `now_s` (newest wins per finger).
  void OnTouchTrace(const v1::TouchTrace& trace, double now_s);
  /// Renders both fingers over `dt_s`; fills `out` (24 + 24 values per finger) and returns true
  /// when a display frame completed.
  bool Tick(double now_s, double dt_s, v1::PinFrame* out);

  std::uint64_t bad_fingers() const { return bad_fingers_; }
  const tactile::RenderCounters& counters(int finger) const { return states_[static_cast<std::size_t>(finger)].counters; }

 private:
  std::unique_ptr<tactile::RendererModel> model_;
  double stale_after_s_;
  std::array<tactile::FingerInput, 2> inputs_{};  // 0 thumb, 1 index
  std::array<double, 2> input_time_s_{-1e9, -1e9};
  std::array<tactile::FingerRenderState, 2> states_{};
  tactile::RenderWorkspace workspace_{};
  std::uint64_t frame_index_ = 0;
  std::uint64_t bad_fingers_ = 0;
};

}  // namespace haptex::tactile_service
