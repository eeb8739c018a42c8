#include "launch/figure_curves.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace haptex::launch {
namespace {

constexpr int kStick = 4;  // contact state IV
constexpr int kSlide = 5;  // contact state V

// Nearest-rank percentile of `values` (sorted in place); 0 for none.
double Percentile(std::vector<double>* values, double fraction) {
  if (values->empty()) return 0.0;
  std::sort(values->begin(), values->end());
  const auto rank = static_cast<std::size_t>(std::lround(fraction * static_cast<double>(values->size() - 1)));
  return (*values)[std::min(rank, values->size() - 1)];
}

}  // namespace

StickSlipFigure MeasureStickSlip(const std::vector<FrictionSample>& samples, const StickSlipOptions& options) {
  struct Peak {
    double ratio, t_s;
  };
  StickSlipFigure figure;
  std::vector<Peak> peaks;
  std::vector<Peak> stick;  // the samples of the present stick run of a pressed finger
  std::vector<double> slide;
  Peak run_max{0.0, 0.0};     // the break-away's largest ratio so far
  bool sliding = false;       // in a slide run
  int slide_index = 0;        // samples of the slide run so far
  bool seeking_peak = false;  // within peak_after_slide_samples of a break-away
  const auto close_peak = [&] {
    if (seeking_peak) peaks.push_back(run_max);
    seeking_peak = false;
  };
  for (const FrictionSample& s : samples) {
    const bool pressed = s.normal_N >= options.min_normal_N && (s.contact_state == kStick || s.contact_state == kSlide);
    if (!pressed) {  // lifted, or another state: whatever comes next starts afresh
      close_peak();
      stick.clear();
      sliding = false;
      continue;
    }
    const double ratio = s.tangential_N / s.normal_N;
    if (s.contact_state == kStick) {
      close_peak();
      stick.push_back({ratio, s.t_s});
      sliding = false;
      continue;
    }
    if (!sliding) {
      sliding = true;
      slide_index = 0;
      seeking_peak = !stick.empty();  // a break-away only from a stick of the same press
      run_max = {0.0, 0.0};
      const std::size_t tail =
          std::min(stick.size(), static_cast<std::size_t>(std::max(0, options.peak_before_slide_samples)));
      for (auto p = stick.end() - static_cast<std::ptrdiff_t>(tail); p != stick.end(); ++p) {
        if (p->ratio > run_max.ratio) run_max = *p;
      }
      stick.clear();
    }
    if (seeking_peak && slide_index >= options.peak_after_slide_samples) close_peak();
    if (seeking_peak && ratio > run_max.ratio) run_max = {ratio, s.t_s};
    if (slide_index >= options.settle_samples) slide.push_back(ratio);
    ++slide_index;
  }
  close_peak();
  figure.breakaways = static_cast<int>(peaks.size());
  if (!peaks.empty()) {
    figure.first_peak = peaks.front().ratio;
    figure.first_peak_t_s = peaks.front().t_s;
    std::vector<double> ratios;
    for (const Peak& p : peaks) ratios.push_back(p.ratio);
    figure.peak_median = Percentile(&ratios, 0.5);  // sorts them
    figure.peak_min = ratios.front();
    figure.peak_max = ratios.back();
  }
  figure.slide_samples = slide.size();
  figure.slide_p10 = Percentile(&slide, 0.1);
  figure.slide_median = Percentile(&slide, 0.5);
  figure.slide_p90 = Percentile(&slide, 0.9);
  return figure;
}

double StripForceN(const TensileStrip& strip, double elongation_m) {
  return strip.width_m * strip.force_per_width_N_per_m(elongation_m / strip.rest_length_m);
}

ForceElongationFigure CompareWithTensileCurve(const std::vector<StretchSample>& samples, const TensileStrip& strip) {
  ForceElongationFigure figure;
  double sum_squares = 0.0;
  for (const StretchSample& s : samples) {
    if (s.elongation_m < 0.0) continue;
    const double difference = s.force_N - StripForceN(strip, s.elongation_m);
    ++figure.samples;
    sum_squares += difference * difference;
    figure.max_difference_N = std::max(figure.max_difference_N, std::abs(difference));
    figure.max_elongation_m = std::max(figure.max_elongation_m, s.elongation_m);
  }
  if (figure.samples == 0) return figure;
  figure.rms_difference_N = std::sqrt(sum_squares / static_cast<double>(figure.samples));
  figure.curve_peak_N = StripForceN(strip, figure.max_elongation_m);
  if (figure.curve_peak_N > 0.0) figure.rms_percent_of_peak = 100.0 * figure.rms_difference_N / figure.curve_peak_N;
  return figure;
}

}  // namespace haptex::launch
