#include "services/tactile/tactile_loop.h"

#include <gtest/gtest.h>

#include "libs/tactile/periodicity.h"
#include "libs/tactile/weave_surface.h"
#include "tests/support/allocation_counter.h"
#include "tests/support/captured_outbox.h"
#include "tests/support/wrap_envelope.h"

namespace haptex::tactile_service {
namespace {

std::unique_ptr<tactile::RendererModel> PlainWeaveModel() {
  tactile::WeaveParams weave;
  weave.warp_pitch_m = weave.weft_pitch_m = 1e-3;
  weave.yarn_diameter_m = 0.6e-3;
  weave.smd_um = 5.0;
  weave.pixel_size_m = 1e-3 / 12;
  weave.size_x = weave.size_y = 256;
  return std::make_unique<tactile::RendererModel>(tactile::AnalysePeriodicity(tactile::GenerateWeave(weave)));
}

v1::TouchTrace Sliding(double speed_m_per_s, bool contact) {
  v1::TouchTrace trace;
  auto* thumb = trace.add_fingers();
  thumb->set_finger(v1::FINGER_THUMB);
  thumb->set_in_contact(contact);
  thumb->set_slip_u_m_per_s(speed_m_per_s);
  thumb->set_normal_force_n(1.0);
  return trace;
}

double MaxAmplitude(const v1::PinFrame& frame) {
  double peak = 0;
  for (const auto& finger : frame.fingers()) {
    for (float a : finger.amplitude_40hz()) peak = std::max<double>(peak, a);
    for (float a : finger.amplitude_320hz()) peak = std::max<double>(peak, a);
  }
  return peak;
}

// Runs the loop at 500 Hz for `seconds`, feeding `trace` every tick unless it is null.
double RunAt500Hz(TactileLoop& loop, double* t, double seconds, const v1::TouchTrace* trace, v1::PinFrame* frame,
                  v1::TouchTrace* moving = nullptr) {
  double peak = 0;
  for (int k = 0; k < static_cast<int>(seconds * 500); ++k) {
    *t += 0.002;
    if (trace != nullptr) {
      if (moving != nullptr) {
        // the touch point moves with the slip velocity
        moving->mutable_fingers(0)->set_u_m(moving->fingers(0).u_m() + 0.002 * moving->fingers(0).slip_u_m_per_s());
        loop.OnTouchTrace(*moving, *t);
      } else {
        loop.OnTouchTrace(*trace, *t);
      }
    }
    if (loop.Tick(*t, 0.002, frame)) peak = MaxAmplitude(*frame);
  }
  return peak;
}

TEST(TactileLoopTest, SilentWithoutContactVibratesWhileSlidingSilentWhenTracesStop) {
  TactileLoop loop(PlainWeaveModel());
  v1::PinFrame frame;
  double t = 0;
  EXPECT_EQ(RunAt500Hz(loop, &t, 0.2, nullptr, &frame), 0.0);  // nothing from local_contact yet
  ASSERT_EQ(frame.fingers_size(), 2);
  EXPECT_EQ(frame.fingers(0).amplitude_40hz_size(), 24);
  const v1::TouchTrace resting = Sliding(0.0, true);
  EXPECT_EQ(RunAt500Hz(loop, &t, 0.2, &resting, &frame), 0.0);  // contact, no sliding
  v1::TouchTrace sliding = Sliding(0.04, true);
  EXPECT_GT(RunAt500Hz(loop, &t, 0.3, &sliding, &frame, &sliding), 0.0);  // 40 mm/s over 1 mm threads
  EXPECT_EQ(RunAt500Hz(loop, &t, 0.3, nullptr, &frame), 0.0);             // traces stopped: stale, silent
  EXPECT_GT(frame.frame_index(), 100u);
}

TEST(TactileLoopTest, UnknownFingersAreCounted) {
  TactileLoop loop(PlainWeaveModel());
  v1::TouchTrace trace;
  trace.add_fingers()->set_finger(v1::FINGER_UNSPECIFIED);
  loop.OnTouchTrace(trace, 0.0);
  EXPECT_EQ(loop.bad_fingers(), 1u);
}

TEST(TactileLoopTest, WarmedUpTickDoesNotAllocate) {
  if (!testing::AllocationCountingSupported()) GTEST_SKIP();
  TactileLoop loop(PlainWeaveModel());
  v1::PinFrame frame;
  v1::TouchTrace sliding = Sliding(0.1, true);
  double t = 0;
  RunAt500Hz(loop, &t, 0.2, &sliding, &frame, &sliding);  // warm-up: the message gets its fingers
  testing::AllocationCounter counter;
  RunAt500Hz(loop, &t, 0.2, &sliding, &frame, &sliding);
  EXPECT_EQ(counter.count(), 0);
}

// As the service runs it: received envelopes in, PinFrames to the display out through the Outbox,
// the counters in Health, silence on the way out; and the same cycle does not allocate.
TEST(TactileLoopTest, EnvelopesInPinFramesToTheDisplayOut) {
  constexpr services::PeerId kDisplay = 3;
  runtime::HealthReporter health("tactile");
  TactileLoop loop(PlainWeaveModel(), TactileLoop::kDefaultStaleAfterS, kDisplay, &health);
  testing::CapturedOutbox out;
  v1::TouchTrace sliding = Sliding(0.04, true);
  for (int k = 1; k <= 150; ++k) {
    const double t = k * 0.002;
    sliding.mutable_fingers(0)->set_u_m(0.04 * t);
    loop.Read(testing::WrapEnvelope(sliding, static_cast<std::uint64_t>(k)), t);
    loop.Update(t, 0.002);
    loop.Write(out);
  }
  const auto frames = out.Of<v1::PinFrame>(kDisplay);
  ASSERT_GT(frames.size(), 100u);
  EXPECT_EQ(frames.size(), loop.frames_sent());
  EXPECT_GT(MaxAmplitude(frames.back()), 0.0);
  EXPECT_EQ(loop.touch_traces(), 150u);
  std::uint64_t sent = 0;
  for (const auto& c : health.Build(0.0).counters()) {
    if (c.name() == "pin_frames_sent") sent = c.value();
  }
  EXPECT_EQ(sent, loop.frames_sent());
  out.Clear();
  loop.WriteSilence(out);
  ASSERT_EQ(out.Of<v1::PinFrame>(kDisplay).size(), 1u);
  EXPECT_EQ(MaxAmplitude(out.Of<v1::PinFrame>(kDisplay)[0]), 0.0);

  if (!testing::AllocationCountingSupported()) return;
  out.capture = false;
  const v1::Envelope envelope = testing::WrapEnvelope(sliding, 1000);
  testing::AllocationCounter counter;
  for (int k = 151; k <= 300; ++k) {
    loop.Read(envelope, k * 0.002);
    loop.Update(k * 0.002, 0.002);
    loop.Write(out);
  }
  EXPECT_EQ(counter.count(), 0);
}

}  // namespace
}  // namespace haptex::tactile_service
