#pragma once
// The paper's section 6 figures measured from a run's series (pure: numbers in, numbers out; no
// files, clocks or messages). Fig. 9: the stick peak and the sliding plateau of one finger's
// F_T/F_N. Fig. 10: the force along the stretch against the elongation of a clamped strip,
// compared with the fabric's own tensile curve.

#include <cstddef>
#include <functional>
#include <vector>

namespace haptex::launch {

/// One finger's contact forces at one tick and the state the contact was named.
struct FrictionSample {
  double t_s = 0.0;
  double normal_N = 0.0;
  double tangential_N = 0.0;
  int contact_state = 0;  ///< 1..9 = I..IX; only IV (sticks) and V (slides) are one finger on the fabric
};

struct StickSlipOptions {
  /// Below this normal force the ratio says nothing (a finger grazing the fabric).
  double min_normal_N = 0.05;
  // The windows below count samples, one per haptic tick, not seconds: the state classifier's
  // filter counts ticks, and a stall of the host drops ticks from the series (a 50 ms gap) while
  // the contact moves on by one tick only.
  /// The classifier names a slide up to about 15 ticks after the contact broke away (its state
  /// filter), so the break-away peak is looked for until this many samples after the state says V.
  int peak_after_slide_samples = 20;
  /// ... and from this many before it: the stick's end, where it broke. Earlier in the stick the
  /// ratio says how the finger met the fabric (a finger pressed on at a slant starts high), not
  /// where it broke away.
  int peak_before_slide_samples = 30;
  /// The start of each slide is the break-away transient, not the plateau: left out of it. A
  /// finger pulled by the user's spring slides only some 60 ticks before it sticks again
  /// (stick-slip), and its ratio settles within about 20 ticks of the break-away.
  int settle_samples = 20;
};

struct StickSlipFigure {
  int breakaways = 0;     ///< sticking (IV) turned to sliding (V) with the finger pressed throughout
  double first_peak = 0;  ///< largest F_T/F_N of the first break-away (its peak window)
  double first_peak_t_s = 0;
  double peak_min = 0, peak_median = 0, peak_max = 0;     ///< of every break-away's peak
  std::size_t slide_samples = 0;                          ///< sliding samples past settle_samples
  double slide_median = 0, slide_p10 = 0, slide_p90 = 0;  ///< their F_T/F_N
};

/// Stick-slip of one finger from its samples in time order. No break-away: breakaways 0 (and the
/// plateau still from any sliding samples).
StickSlipFigure MeasureStickSlip(const std::vector<FrictionSample>& samples, const StickSlipOptions& options = {});

/// The fingers pulling a strip: how far they have pulled it since they pinched it, and the force
/// along the pull with which it holds them back (> 0 resists).
struct StretchSample {
  double elongation_m = 0.0;
  double force_N = 0.0;
};

/// The strip the fingers pull: clamped `rest_length_m` from the pinch, `width_m` across, its
/// force per width against strain the fabric's tensile curve along the pull [N/m].
struct TensileStrip {
  double rest_length_m = 0.0;
  double width_m = 0.0;
  std::function<double(double strain)> force_per_width_N_per_m;
};

struct ForceElongationFigure {
  std::size_t samples = 0;         ///< compared: those at elongation >= 0
  double max_elongation_m = 0;     ///< of the compared samples
  double curve_peak_N = 0;         ///< the fabric's force at max_elongation_m
  double rms_difference_N = 0;     ///< measured - fabric, over the compared samples
  double max_difference_N = 0;     ///< largest |measured - fabric|
  double rms_percent_of_peak = 0;  ///< 100 rms_difference_N / curve_peak_N (0 when the peak is 0)
};

/// The fabric's force for a strip pulled by `elongation_m`: width x f(elongation / rest length).
double StripForceN(const TensileStrip& strip, double elongation_m);

/// Compares each sample with StripForceN at its elongation.
ForceElongationFigure CompareWithTensileCurve(const std::vector<StretchSample>& samples, const TensileStrip& strip);

}  // namespace haptex::launch
