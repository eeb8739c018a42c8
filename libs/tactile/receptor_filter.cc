#include "libs/tactile/receptor_filter.h"

#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string>

namespace haptex::tactile {
namespace {

void CheckCorner(double corner_hz, double q, double sample_rate_hz) {
  if (!(sample_rate_hz > 0.0) || !(corner_hz > 0.0) || !(corner_hz < 0.5 * sample_rate_hz) || !(q > 0.0)) {
    throw std::invalid_argument("biquad: need 0 < corner (" + std::to_string(corner_hz) + " Hz) < sample rate / 2 (" +
                                std::to_string(sample_rate_hz) + " Hz) and Q > 0");
  }
}

// Common bilinear design with pre-warped corner; numerator picked by the caller.
Biquad Design(double corner_hz, double q, double sample_rate_hz, bool high_pass) {
  CheckCorner(corner_hz, q, sample_rate_hz);
  const double w0 = 2.0 * std::numbers::pi * corner_hz / sample_rate_hz;
  const double cosw = std::cos(w0);
  const double alpha = std::sin(w0) / (2.0 * q);
  const double a0 = 1.0 + alpha;
  Biquad c;
  if (high_pass) {
    c.b0 = (1.0 + cosw) / 2.0 / a0;
    c.b1 = -(1.0 + cosw) / a0;
  } else {
    c.b0 = (1.0 - cosw) / 2.0 / a0;
    c.b1 = (1.0 - cosw) / a0;
  }
  c.b2 = c.b0;
  c.a1 = -2.0 * cosw / a0;
  c.a2 = (1.0 - alpha) / a0;
  return c;
}

}  // namespace

Biquad DesignLowPass(double corner_hz, double q, double sample_rate_hz) {
  return Design(corner_hz, q, sample_rate_hz, false);
}

Biquad DesignHighPass(double corner_hz, double q, double sample_rate_hz) {
  return Design(corner_hz, q, sample_rate_hz, true);
}

double BiquadMagnitude(const Biquad& c, double frequency_hz, double sample_rate_hz) {
  const std::complex<double> z1 = std::polar(1.0, -2.0 * std::numbers::pi * frequency_hz / sample_rate_hz);
  const std::complex<double> z2 = z1 * z1;
  return std::abs((c.b0 + c.b1 * z1 + c.b2 * z2) / (1.0 + c.a1 * z1 + c.a2 * z2));
}

ThresholdCurve::ThresholdCurve(std::vector<std::pair<double, double>> points) : points_(std::move(points)) {
  if (points_.size() < 2) throw std::invalid_argument("ThresholdCurve: need at least two points");
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!(points_[i].first > 0.0) || !std::isfinite(points_[i].first) || !std::isfinite(points_[i].second)) {
      throw std::invalid_argument("ThresholdCurve: frequencies must be > 0 and values finite");
    }
    if (i > 0 && !(points_[i].first > points_[i - 1].first)) {
      throw std::invalid_argument("ThresholdCurve: frequencies must increase strictly");
    }
  }
}

double ThresholdCurve::ThresholdDb(double frequency_hz) const {
  std::size_t i = 1;
  while (i + 1 < points_.size() && frequency_hz > points_[i].first) ++i;
  const auto& [f0, d0] = points_[i - 1];
  const auto& [f1, d1] = points_[i];
  const double t = std::log2(frequency_hz / f0) / std::log2(f1 / f0);
  return d0 + t * (d1 - d0);
}

double ThresholdCurve::ThresholdUm(double frequency_hz) const {
  return std::pow(10.0, ThresholdDb(frequency_hz) / 20.0);
}

ThresholdCurve ThresholdCurve::DefaultRa() {
  return ThresholdCurve({{10, 18}, {20, 13}, {40, 10}, {80, 13}, {160, 20}, {320, 28}, {640, 36}});
}

ThresholdCurve ThresholdCurve::DefaultPc() {
  return ThresholdCurve({{10, 36}, {20, 24}, {40, 12}, {80, 1}, {160, -8}, {250, -10}, {320, -9}, {640, 0}});
}

ReceptorChannelShape DefaultRaShape() { return {15.0, 0.4, 120.0, 0.3, 40.0}; }

ReceptorChannelShape DefaultPcShape() { return {220.0, 0.5, 250.0, 0.707, 250.0}; }

ReceptorChannelFilter::ReceptorChannelFilter(const ReceptorChannelShape& shape, const ThresholdCurve& threshold,
                                             double sample_rate_hz)
    : high_pass_(DesignHighPass(shape.high_pass_hz, shape.high_pass_q, sample_rate_hz)),
      low_pass_(DesignLowPass(shape.low_pass_hz, shape.low_pass_q, sample_rate_hz)),
      sample_rate_hz_(sample_rate_hz) {
  if (!(shape.reference_hz > 0.0) || !(shape.reference_hz < 0.5 * sample_rate_hz)) {
    throw std::invalid_argument("ReceptorChannelShape: reference_hz must be in (0, sample rate / 2)");
  }
  const double raw = BiquadMagnitude(high_pass_, shape.reference_hz, sample_rate_hz) *
                     BiquadMagnitude(low_pass_, shape.reference_hz, sample_rate_hz);
  gain_per_um_ = 1.0 / (raw * threshold.ThresholdUm(shape.reference_hz));
}

double ReceptorChannelFilter::ResponsePerUm(double frequency_hz) const {
  return gain_per_um_ * BiquadMagnitude(high_pass_, frequency_hz, sample_rate_hz_) *
         BiquadMagnitude(low_pass_, frequency_hz, sample_rate_hz_);
}

}  // namespace haptex::tactile
