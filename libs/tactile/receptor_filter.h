#pragma once
// Receptor-channel filters (docs/tactile.md section 6 step 6; the thresholds: section 7): per
// channel a band-pass whose magnitude follows the inverse detection threshold, normalised so that a
// sinusoid at threshold gives excitation 1 ("threshold units").

#include <utility>
#include <vector>

namespace haptex::tactile {

/// Second-order section, a0 normalised to 1: y = b0 x + b1 x1 + b2 x2 - a1 y1 - a2 y2.
struct Biquad {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
};

/// Bilinear-transform designs with the corner frequency pre-warped.
Biquad DesignLowPass(double corner_hz, double q, double sample_rate_hz);
Biquad DesignHighPass(double corner_hz, double q, double sample_rate_hz);
/// |H(e^{j 2 pi f / fs})|.
double BiquadMagnitude(const Biquad& biquad, double frequency_hz, double sample_rate_hz);

/// Transposed direct form II state.
struct BiquadState {
  double z1 = 0.0, z2 = 0.0;
  double Process(const Biquad& c, double x) {
    const double y = c.b0 * x + z1;
    z1 = c.b1 * x - c.a1 * y + z2;
    z2 = c.b2 * x - c.a2 * y;
    return y;
  }
  /// Steady state for a constant input x (no start-up transient).
  void Reset(const Biquad& c, double x) {
    const double gain = (c.b0 + c.b1 + c.b2) / (1.0 + c.a1 + c.a2);
    const double y = gain * x;
    z2 = c.b2 * x - c.a2 * y;
    z1 = y - c.b0 * x;
  }
};

/// Detection threshold vs frequency: displacement [um peak], piecewise linear in dB over log2 f,
/// extrapolated from the end segments.
class ThresholdCurve final {
 public:
  /// @param points (frequency [Hz], threshold [dB re 1 um]) with strictly increasing frequencies.
  /// @throws std::invalid_argument with fewer than two points, unsorted or non-finite entries.
  explicit ThresholdCurve(std::vector<std::pair<double, double>> points);
  double ThresholdDb(double frequency_hz) const;
  double ThresholdUm(double frequency_hz) const;
  const std::vector<std::pair<double, double>>& points() const { return points_; }

  /// NP I (RA, Meissner) illustrative table of docs/tactile.md section 7.
  static ThresholdCurve DefaultRa();
  /// P (PC, Pacinian) illustrative table of docs/tactile.md section 7.
  static ThresholdCurve DefaultPc();

 private:
  std::vector<std::pair<double, double>> points_;
};

/// Filter shape of one channel: 2nd-order high-pass then 2nd-order low-pass. The defaults are
/// least-squares fits (in dB) to the default threshold tables: RA 0.8 dB rms over 10-640 Hz,
/// PC 0.2 dB rms.
struct ReceptorChannelShape {
  double high_pass_hz = 15.0;
  double high_pass_q = 0.4;
  double low_pass_hz = 120.0;
  double low_pass_q = 0.3;
  /// Frequency where the gain is pinned to 1 / threshold.
  double reference_hz = 40.0;
};

ReceptorChannelShape DefaultRaShape();
ReceptorChannelShape DefaultPcShape();

/// Designed filter of one channel: input height [um], output in threshold units.
class ReceptorChannelFilter final {
 public:
  /// @throws std::invalid_argument if corners are not below Nyquist or Q <= 0.
  ReceptorChannelFilter(const ReceptorChannelShape& shape, const ThresholdCurve& threshold, double sample_rate_hz);

  const Biquad& high_pass() const { return high_pass_; }
  const Biquad& low_pass() const { return low_pass_; }
  double gain_per_um() const { return gain_per_um_; }
  /// |W(f)| [1/um]: excitation in threshold units per um of sinusoid amplitude.
  double ResponsePerUm(double frequency_hz) const;

 private:
  Biquad high_pass_;
  Biquad low_pass_;
  double gain_per_um_ = 1.0;
  double sample_rate_hz_;
};

}  // namespace haptex::tactile
