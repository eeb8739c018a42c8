#pragma once
// What a pin display accepts: per finger 24 amplitudes per channel, finite, within [0, 1].

#include <string_view>

#include "haptex/v1/pin_frame.pb.h"

namespace haptex::mock_pins {

inline constexpr int kPinRows = 6;
inline constexpr int kPinColumns = 4;
inline constexpr int kPinsPerFinger = kPinRows * kPinColumns;

enum class PinFrameProblem { kNone, kNoFingers, kTooManyFingers, kBadFinger, kWrongPinCount, kOutOfRange };

/// The first problem of a frame, or kNone. A display drives nothing from a bad frame.
PinFrameProblem CheckPinFrame(const v1::PinFrame& frame);
std::string_view PinFrameProblemName(PinFrameProblem problem);

}  // namespace haptex::mock_pins
