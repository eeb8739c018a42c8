#include "libs/textile/kes_material.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace haptex::textile {
namespace {

[[noreturn]] void Fail(const std::string& fabric, const std::string& field, const std::string& why, double value) {
  std::ostringstream msg;
  if (!fabric.empty()) msg << "fabric '" << fabric << "': ";
  msg << field << " " << why << " (got " << value << ")";
  throw std::invalid_argument(msg.str());
}

void RequirePositive(const std::string& fabric, const std::string& field, double value) {
  if (!std::isfinite(value) || !(value > 0.0)) {
    Fail(fabric, field, value == 0.0 ? "is missing (must be > 0)" : "must be finite and > 0", value);
  }
}

void RequireNonNegative(const std::string& fabric, const std::string& field, double value) {
  if (!std::isfinite(value) || value < 0.0) Fail(fabric, field, "must be finite and >= 0", value);
}

// The tensile law with its compression branch: slope compression_fraction x the curve's
// small-strain stiffness (its tangent at zero strain, never below the floor fraction of the
// secant, so a toe region that starts flat still resists compression). docs/fabric-model.md
// section 2 gives the reasons: a bent region of the grid-line bending elements pulls its
// segments shorter with B kappa^2 per width, and a fabric contracts by that over this slope
// instead of keeping its length; a stiff branch also makes the mesh buckle out of plane at small
// compression, as fabric does.
StrainCurve WithCompression(MonotoneSpline loading, double secant_N_per_m, const KesConversionOptions& options) {
  const double small_strain_N_per_m =
      std::max(loading.tangents().front(), options.tensile_floor_fraction * secant_N_per_m);
  return StrainCurve::Tensile(std::move(loading), options.compression_fraction * small_strain_N_per_m);
}

StrainCurve CurveFromPoints(const kes::KesTensile& t, const std::string& field, const KesConversionOptions& options) {
  std::vector<double> x, y;
  x.reserve(t.loading_curve.size() + 1);
  y.reserve(t.loading_curve.size() + 1);
  for (std::size_t k = 0; k < t.loading_curve.size(); ++k) {
    const auto& p = t.loading_curve[k];
    const std::string name = field + ".loading_curve[" + std::to_string(k) + "]";
    RequireNonNegative("", name + ".x", p.x);
    RequireNonNegative("", name + ".y", p.y);
    if (k == 0 && p.x > 0.0) {
      x.push_back(0.0);
      y.push_back(0.0);
    }
    if (!x.empty() && !(p.x > x.back())) Fail("", name + ".x", "must increase strictly", p.x);
    if (!y.empty() && p.y * kGfPerCmToNPerM < y.back()) {
      Fail("", name + ".y", "must not decrease (loading curve)", p.y);
    }
    x.push_back(p.x);
    y.push_back(p.y * kGfPerCmToNPerM);
  }
  if (y.front() != 0.0) Fail("", field + ".loading_curve[0].y", "must be 0 at zero strain", y[0]);
  if (x.size() < 2 || !(y.back() > 0.0)) {
    throw std::invalid_argument(field + ".loading_curve: needs a point with positive force");
  }
  const double secant = y.back() / x.back();
  return WithCompression(MonotoneSpline(std::move(x), std::move(y)), secant, options);
}

}  // namespace

StrainCurve TensileCurveFromKes(const kes::KesTensile& t, const std::string& field,
                                const KesConversionOptions& options) {
  if (!(options.compression_fraction >= 0.0) || !(options.tensile_floor_fraction >= 0.0) ||
      options.reconstruction_knots < 3) {
    throw std::invalid_argument("KesConversionOptions: fractions must be >= 0 and knots >= 3");
  }
  if (!t.loading_curve.empty()) {
    try {
      return CurveFromPoints(t, field, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("tensile curve: ") + e.what());
    }
  }
  // Reconstruction from the summary values (power law, docs/physics-reference.md section 2.2).
  RequirePositive("", field + ".emt_percent", t.emt_percent);
  RequirePositive("", field + ".lt", t.lt);
  RequireNonNegative("", field + ".fm_gf_per_cm", t.fm_gf_per_cm);
  if (!(t.lt < 2.0)) Fail("", field + ".lt", "must be < 2 for a power-law reconstruction", t.lt);
  const double em = t.emt_percent / 100.0;
  const double fm_N_per_m = (t.fm_gf_per_cm > 0.0 ? t.fm_gf_per_cm : kStandardFmGfPerCm) * kGfPerCmToNPerM;
  const double n = 2.0 / t.lt - 1.0;
  const double secant = fm_N_per_m / em;
  const double floor = options.tensile_floor_fraction * secant;
  const int knots = options.reconstruction_knots;
  std::vector<double> x(static_cast<std::size_t>(knots)), y(static_cast<std::size_t>(knots));
  for (int k = 0; k < knots; ++k) {
    // Knots denser near zero strain, where the haptic loads live.
    const double s = std::pow(static_cast<double>(k) / (knots - 1), 1.5);
    const double e = em * s;
    x[static_cast<std::size_t>(k)] = e;
    y[static_cast<std::size_t>(k)] = std::max(fm_N_per_m * std::pow(s, n), floor * e);
  }
  return WithCompression(MonotoneSpline(std::move(x), std::move(y)), secant, options);
}

FabricMaterial MaterialFromKes(const kes::Fabric& f, const KesConversionOptions& options) {
  const std::string& name = f.name;
  FabricMaterial m;
  m.name = name;
  try {
    m.tensile_warp = TensileCurveFromKes(f.warp_tensile, "warp_tensile", options);
    m.tensile_weft = TensileCurveFromKes(f.weft_tensile, "weft_tensile", options);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("fabric '" + name + "': " + e.what());
  }
  RequirePositive(name, "shear.g_gf_per_cm_deg", f.shear.g_gf_per_cm_deg);
  const double g = f.shear.g_gf_per_cm_deg * kGfPerCmDegToNPerMRad;
  // KES G is the slope over 0.5-5 deg; hysteresis (2HG, 2HG5) is not modelled.
  m.shear = StrainCurve::Odd(MonotoneSpline({0.0, 1.0}, {0.0, g}));
  RequirePositive(name, "warp_bending.b_gfcm2_per_cm", f.warp_bending.b_gfcm2_per_cm);
  RequirePositive(name, "weft_bending.b_gfcm2_per_cm", f.weft_bending.b_gfcm2_per_cm);
  m.bending_warp_Nm = f.warp_bending.b_gfcm2_per_cm * kGfCm2PerCmToNm;
  m.bending_weft_Nm = f.weft_bending.b_gfcm2_per_cm * kGfCm2PerCmToNm;
  RequirePositive(name, "weight_mg_per_cm2", f.weight_mg_per_cm2);
  m.density_kg_per_m2 = f.weight_mg_per_cm2 * kMgPerCm2ToKgPerM2;
  RequireNonNegative(name, "thickness_mm", f.thickness_mm);
  m.thickness_m = f.thickness_mm * 1e-3;
  return m;
}

}  // namespace haptex::textile
