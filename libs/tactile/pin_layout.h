#pragma once
// The fingertip pin array: 6 x 4 contactors at 2 mm pitch (Exeter HAPTEX stimulator).

#include <cmath>

#include <Eigen/Core>

#include "libs/base/demand.h"

namespace haptex::tactile {

/// Pin (i, j), i = 0..5 along the finger's long axis, j = 0..3 across, has index i + 6 j.
/// Its offset in the fingertip frame is ((i - 2.5) pitch, (j - 1.5) pitch): centred on the
/// touch point.
struct PinLayout {
  static constexpr int kColumns = 6;
  static constexpr int kRows = 4;
  static constexpr int kPinCount = kColumns * kRows;

  double pitch_m = 2e-3;

  static constexpr int Index(int i, int j) { return i + kColumns * j; }

  /// Offset of pin `index` in the fingertip frame [m].
  Eigen::Vector2d OffsetOnFingerM(int index) const {
    HAPTEX_DEMAND(index >= 0 && index < kPinCount);  // a caller bug
    const int i = index % kColumns;
    const int j = index / kColumns;
    return {(i - 0.5 * (kColumns - 1)) * pitch_m, (j - 0.5 * (kRows - 1)) * pitch_m};
  }

  /// Offset of pin `index` in fabric coordinates for a finger whose long axis makes
  /// `orientation_rad` with the fabric's u axis [m].
  Eigen::Vector2d OffsetOnFabricM(int index, double orientation_rad) const {
    const Eigen::Vector2d f = OffsetOnFingerM(index);
    const double c = std::cos(orientation_rad), s = std::sin(orientation_rad);
    return {c * f.x() - s * f.y(), s * f.x() + c * f.y()};
  }
};

}  // namespace haptex::tactile
