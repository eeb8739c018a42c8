#include "services/mock_pins/pin_frame_check.h"

#include <gtest/gtest.h>

#include <limits>

#include "tests/services/mock_pins/pin_test_frames.h"

namespace haptex::mock_pins {
namespace {

TEST(PinFrameCheckTest, AcceptsAValidFrame) { EXPECT_EQ(CheckPinFrame(testing::RampFrame(1)), PinFrameProblem::kNone); }

TEST(PinFrameCheckTest, RefusesEachKindOfBadFrame) {
  EXPECT_EQ(CheckPinFrame(v1::PinFrame{}), PinFrameProblem::kNoFingers);
  auto three = testing::RampFrame(1);
  *three.add_fingers() = three.fingers(0);
  EXPECT_EQ(CheckPinFrame(three), PinFrameProblem::kTooManyFingers);
  auto unnamed = testing::RampFrame(1);
  unnamed.mutable_fingers(1)->set_finger(v1::FINGER_UNSPECIFIED);
  EXPECT_EQ(CheckPinFrame(unnamed), PinFrameProblem::kBadFinger);
  auto twice = testing::RampFrame(1);
  twice.mutable_fingers(1)->set_finger(v1::FINGER_THUMB);
  EXPECT_EQ(CheckPinFrame(twice), PinFrameProblem::kBadFinger);
  auto short_frame = testing::RampFrame(1);
  short_frame.mutable_fingers(0)->mutable_amplitude_320hz()->RemoveLast();
  EXPECT_EQ(CheckPinFrame(short_frame), PinFrameProblem::kWrongPinCount);
  for (float bad : {-0.1f, 1.5f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    auto frame = testing::RampFrame(1);
    frame.mutable_fingers(1)->set_amplitude_320hz(5, bad);
    EXPECT_EQ(CheckPinFrame(frame), PinFrameProblem::kOutOfRange) << bad;
  }
}

}  // namespace
}  // namespace haptex::mock_pins
