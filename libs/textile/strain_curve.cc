#include "libs/textile/strain_curve.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace haptex::textile {

StrainCurve StrainCurve::Tensile(MonotoneSpline loading, double compression_N_per_m) {
  if (!std::isfinite(compression_N_per_m) || compression_N_per_m < 0.0) {
    throw std::invalid_argument("StrainCurve: compression stiffness must be finite and >= 0");
  }
  StrainCurve c;
  c.loading_ = std::move(loading);
  c.compression_N_per_m_ = compression_N_per_m;
  c.odd_ = false;
  return c;
}

StrainCurve StrainCurve::Odd(MonotoneSpline loading) {
  StrainCurve c;
  c.loading_ = std::move(loading);
  c.odd_ = true;
  return c;
}

void StrainCurve::Evaluate(double x, double* f, double* df) const {
  if (x >= 0.0) {
    loading_.Evaluate(x, f, df);
    return;
  }
  if (odd_) {
    loading_.Evaluate(-x, f, df);
    *f = -*f;
    return;
  }
  *f = compression_N_per_m_ * x;
  *df = compression_N_per_m_;
}

double StrainCurve::Value(double x) const {
  double f = 0, d = 0;
  Evaluate(x, &f, &d);
  return f;
}

double StrainCurve::MaxSlopeOverData() const {
  double s = compression_N_per_m_;
  for (double m : loading_.tangents()) s = std::max(s, m);
  return s;
}

}  // namespace haptex::textile
