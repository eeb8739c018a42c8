#include "libs/tactile/tactile_colour.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace haptex::tactile {

ColourMatcher::ColourMatcher(double ra_at_low, double ra_at_high, double pc_at_low, double pc_at_high)
    : m00_(ra_at_low * ra_at_low),
      m01_(ra_at_high * ra_at_high),
      m10_(pc_at_low * pc_at_low),
      m11_(pc_at_high * pc_at_high) {
  const double det = m00_ * m11_ - m01_ * m10_;
  if (!(m00_ > 0.0) || !(m11_ > 0.0) || !std::isfinite(det) || !(std::abs(det) > 1e-6 * m00_ * m11_)) {
    throw std::invalid_argument("ColourMatcher: channel responses at the primaries do not separate RA and PC");
  }
  i00_ = m11_ / det;
  i01_ = -m01_ / det;
  i10_ = -m10_ / det;
  i11_ = m00_ / det;
}

TactileColour ColourMatcher::Match(double excitation_ra, double excitation_pc) const {
  const double ra2 = excitation_ra * excitation_ra;
  const double pc2 = excitation_pc * excitation_pc;
  double lo2 = i00_ * ra2 + i01_ * pc2;
  double hi2 = i10_ * ra2 + i11_ * pc2;
  TactileColour out;
  // Outside the gamut one primary is dropped and the other matches its own channel. Targets on
  // the boundary (a pure primary) land here too through rounding and envelope ripple, so only a
  // miss of the other channel by more than ~1 dB of the stronger excitation is flagged.
  const double tolerance = 0.12 * std::max(excitation_ra, excitation_pc);
  if (lo2 < 0.0) {
    lo2 = 0.0;
    hi2 = pc2 / m11_;
    out.out_of_gamut = std::abs(std::sqrt(hi2 * m01_) - excitation_ra) > tolerance;
  } else if (hi2 < 0.0) {
    hi2 = 0.0;
    lo2 = ra2 / m00_;
    out.out_of_gamut = std::abs(std::sqrt(lo2 * m10_) - excitation_pc) > tolerance;
  }
  out.amplitude_low_um = std::sqrt(lo2);
  out.amplitude_high_um = std::sqrt(hi2);
  return out;
}

}  // namespace haptex::tactile
