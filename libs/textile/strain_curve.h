#pragma once
// A material law "force per width vs strain" in SI units, as the forces consume it.

#include "libs/textile/monotone_spline.h"

namespace haptex::textile {

/// Force per width [N/m] as a function of a strain measure [-] (tensile strain, or shear angle in
/// rad). For x >= 0 a monotone spline through the loading data; for x < 0 either odd symmetry
/// (shear) or a linear compression branch of small slope (tensile: fabric buckles).
class StrainCurve {
 public:
  StrainCurve() = default;

  /// Tensile law: `loading` (passing through (0, 0)) for x >= 0, slope `compression_N_per_m`
  /// for x < 0. @throws std::invalid_argument if the compression slope is negative or not finite.
  static StrainCurve Tensile(MonotoneSpline loading, double compression_N_per_m);
  /// Odd law: f(-x) = -f(x) (shear).
  static StrainCurve Odd(MonotoneSpline loading);

  /// Force per width [N/m] and its slope [N/m] at x.
  void Evaluate(double x, double* f_N_per_m, double* df_dx_N_per_m) const;
  double Value(double x) const;

  const MonotoneSpline& loading() const { return loading_; }
  double compression_N_per_m() const { return compression_N_per_m_; }
  bool odd() const { return odd_; }

  /// Largest slope anywhere on the data part of the curve [N/m] (stability estimates).
  double MaxSlopeOverData() const;

 private:
  MonotoneSpline loading_;
  double compression_N_per_m_ = 0.0;
  bool odd_ = false;
};

}  // namespace haptex::textile
