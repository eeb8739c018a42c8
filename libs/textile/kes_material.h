#pragma once
// KES (Kawabata) fabric data -> SI material laws for the simulation (docs/fabric-model.md).

#include <string>

#include "libs/textile/kes_fabric.h"
#include "libs/textile/strain_curve.h"

namespace haptex::textile {

/// Exact unit factors (derived in docs/physics-reference.md section 1.1).
inline constexpr double kGfPerCmToNPerM = 0.980665;                 // gf/cm -> N/m
inline constexpr double kGfCm2PerCmToNm = 9.80665e-5;               // gf cm^2/cm -> N m
inline constexpr double kGfPerCmDegToNPerMRad = 56.18796561619688;  // gf/(cm deg) -> N/m/rad
inline constexpr double kMgPerCm2ToKgPerM2 = 0.01;                  // mg/cm^2 -> kg/m^2
inline constexpr double kStandardFmGfPerCm = 500.0;                 // KES-FB1 standard max load

/// A fabric's material laws in SI units, as the physics consumes them.
struct FabricMaterial {
  std::string name;
  StrainCurve tensile_warp;        ///< force per width [N/m] vs warp strain [-]
  StrainCurve tensile_weft;        ///< force per width [N/m] vs weft strain [-]
  StrainCurve shear;               ///< shear force per width [N/m] vs shear angle [rad]
  double bending_warp_Nm = 0.0;    ///< bending rigidity for curvature along warp [N m]
  double bending_weft_Nm = 0.0;    ///< bending rigidity for curvature along weft [N m]
  double density_kg_per_m2 = 0.0;  ///< mass per area
  double thickness_m = 0.0;        ///< 0 when the source does not give it
};

/// Choices made when turning KES summary values into curves. Defaults are documented in
/// docs/fabric-model.md.
struct KesConversionOptions {
  /// Tensile slope under compression, as a fraction of the curve's small-strain stiffness (its
  /// tangent at zero strain, at least tensile_floor_fraction of the secant Fm/EMT). 1: the
  /// tangent is continuous through zero strain (docs/fabric-model.md section 2).
  double compression_fraction = 1.0;
  /// Minimum tangent of a reconstructed tensile curve, as a fraction of the secant Fm/EMT, so the
  /// curve is never flat at zero strain.
  double tensile_floor_fraction = 0.02;
  /// Knots of a curve reconstructed from (EMT, LT).
  int reconstruction_knots = 24;
};

/// Converts KES data to SI material laws.
/// Tensile: digitized loading curve if present, else the power law F = Fm (e/em)^(2/LT - 1)
/// (which reproduces EMT, LT and so WT), with a floor tangent. Shear: linear G. Bending: B.
/// Mass: W. Thickness: T (optional). Hysteresis (RT, 2HG, 2HG5, 2HB) is not modelled.
/// @throws std::invalid_argument naming the offending field for negative, NaN or missing data.
FabricMaterial MaterialFromKes(const kes::Fabric& fabric, const KesConversionOptions& options = {});

/// The tensile curve for one KES tensile block (exposed for tests). `field` names the block in
/// error messages, e.g. "warp_tensile".
StrainCurve TensileCurveFromKes(const kes::KesTensile& tensile, const std::string& field,
                                const KesConversionOptions& options = {});

}  // namespace haptex::textile
