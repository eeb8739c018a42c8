#pragma once
// "Tactile colour" matching (docs/tactile.md section 1.2): the two drive amplitudes at 40 Hz and
// 320 Hz that reproduce a pin's two channel excitations.

namespace haptex::tactile {

/// Drive amplitudes [um peak] for one pin.
struct TactileColour {
  double amplitude_low_um = 0.0;   ///< at the low primary (40 Hz)
  double amplitude_high_um = 0.0;  ///< at the high primary (320 Hz)
  bool out_of_gamut = false;
};

/// Solves E_RA^2 = A_lo^2 W_RA(lo)^2 + A_hi^2 W_RA(hi)^2 and the same for PC, a linear system in
/// (A_lo^2, A_hi^2), where W_c(f) is channel c's response [1/um] at each primary.
/// Out of gamut (a negative square): that primary is set to 0 and the other matches the channel
/// it mainly drives (low -> RA, high -> PC).
class ColourMatcher final {
 public:
  /// @throws std::invalid_argument if the primaries do not separate the channels (singular system).
  ColourMatcher(double ra_at_low, double ra_at_high, double pc_at_low, double pc_at_high);

  /// Excitations in threshold units (>= 0). Real-time safe.
  TactileColour Match(double excitation_ra, double excitation_pc) const;

 private:
  double m00_, m01_, m10_, m11_;  // squared responses
  double i00_, i01_, i10_, i11_;  // inverse
};

}  // namespace haptex::tactile
