#pragma once
// One display update for one finger.

#include <array>
#include <cstdint>

#include "libs/tactile/pin_layout.h"

namespace haptex::tactile {

/// Drive amplitudes of the 24 pins (index as in PinLayout), normalised to the display's maximum
/// amplitude at each frequency: 0 = off, 1 = full drive. Never NaN.
struct PinFrame {
  std::array<float, PinLayout::kPinCount> amplitude_40hz{};
  std::array<float, PinLayout::kPinCount> amplitude_320hz{};
  std::uint64_t sequence = 0;  ///< frames produced by this finger's renderer state, from 1
};

}  // namespace haptex::tactile
