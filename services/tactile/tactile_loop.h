#pragma once
// The tactile service's work per display tick, apart from sockets. Read: the newest TouchTrace
// per finger. Update: one RenderStep per finger. Write: the PinFrame to the display when a frame
// completed, and to the viewer at most at its frame rate. Allocates nothing once warmed up.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>

#include "haptex/v1/envelope.pb.h"
#include "haptex/v1/pin_frame.pb.h"
#include "haptex/v1/touch_trace.pb.h"
#include "libs/runtime/health_reporter.h"
#include "libs/tactile/pin_renderer.h"
#include "services/common/outbox.h"

namespace haptex::tactile_service {

class TactileLoop final {
 public:
  /// A finger whose last TouchTrace is older than this is silent (local_contact sends one a tick).
  static constexpr double kDefaultStaleAfterS = 0.05;

  /// With `display`, Write sends frames there; with `health` (outliving the loop), the loop's
  /// counters are published.
  explicit TactileLoop(std::unique_ptr<tactile::RendererModel> model, double stale_after_s = kDefaultStaleAfterS,
                       std::optional<services::PeerId> display = std::nullopt,
                       runtime::HealthReporter* health = nullptr);

  /// Also sends the viewer a completed frame at most every `period_s`.
  void SetViewer(services::PeerId viewer, double period_s) {
    viewer_ = viewer;
    viewer_period_s_ = period_s;
  }

  void Read(const v1::Envelope& envelope, double t_s);
  /// Takes the fingers of a TouchTrace received at `now_s` (newest wins per finger).
  void OnTouchTrace(const v1::TouchTrace& trace, double now_s);
  void Update(double t_s, double dt_s);
  void Write(services::Outbox& out);
  /// Every pin at zero to the display (the service is stopping).
  void WriteSilence(services::Outbox& out);

  /// Renders both fingers over `dt_s`; fills `out` (24 + 24 values per finger) and returns true
  /// when a display frame completed.
  bool Tick(double now_s, double dt_s, v1::PinFrame* out);

  std::uint64_t bad_fingers() const { return bad_fingers_; }
  const tactile::RenderCounters& counters(int finger) const {
    return states_[static_cast<std::size_t>(finger)].counters;
  }
  std::uint64_t frames_sent() const { return frames_sent_; }
  std::uint64_t touch_traces() const { return touch_traces_; }

 private:
  std::unique_ptr<tactile::RendererModel> model_;
  double stale_after_s_;
  std::optional<services::PeerId> display_, viewer_;
  double viewer_period_s_ = 0, next_view_s_ = 0, t_s_ = 0;
  runtime::HealthReporter* health_;
  std::array<tactile::FingerInput, 2> inputs_{};  // by codec slot: 0 thumb, 1 index
  std::array<double, 2> input_time_s_{-1e9, -1e9};
  std::array<tactile::FingerRenderState, 2> states_{};
  tactile::RenderWorkspace workspace_{};
  v1::PinFrame frame_;
  bool frame_ready_ = false;
  std::uint64_t frame_index_ = 0;
  std::uint64_t bad_fingers_ = 0, frames_sent_ = 0, touch_traces_ = 0;
  struct CounterIds {
    runtime::HealthReporter::CounterId frames, traces, bad;
  } ids_{};
};

}  // namespace haptex::tactile_service
