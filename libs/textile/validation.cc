#include "libs/textile/validation.h"

#include <random>
#include <string>

namespace haptex::textile::validation {

kes::Fabric CompositeDenim() {
  kes::Fabric f;
  f.name = "test_composite_denim";
  f.description = "TEST ONLY: Kumari & Khurana 2016 denim B tensile + Wang 2011 11 oz denim rest";
  f.warp_tensile.emt_percent = 5.735;
  f.warp_tensile.lt = 0.655;
  f.warp_tensile.wt_gfcm_per_cm2 = 9.400;
  f.warp_tensile.rt_percent = 52.39;
  f.weft_tensile = f.warp_tensile;
  f.shear.g_gf_per_cm_deg = 0.475;
  f.warp_bending.b_gfcm2_per_cm = 0.164;
  f.weft_bending.b_gfcm2_per_cm = 0.247;
  f.weight_mg_per_cm2 = 32.4;
  f.thickness_mm = 1.188;
  return f;
}

namespace {
StrainCurve ScaleCurve(const StrainCurve& c, double s) {
  std::vector<double> y = c.loading().knots_y();
  for (double& v : y) v *= s;
  MonotoneSpline spline(c.loading().knots_x(), y);
  return c.odd() ? StrainCurve::Odd(spline) : StrainCurve::Tensile(spline, s * c.compression_N_per_m());
}
}  // namespace

FabricMaterial ScaleStiffness(const FabricMaterial& m, double factor) {
  FabricMaterial out = m;
  out.name = m.name + "_x" + std::to_string(factor);
  out.tensile_warp = ScaleCurve(m.tensile_warp, factor);
  out.tensile_weft = ScaleCurve(m.tensile_weft, factor);
  out.shear = ScaleCurve(m.shear, factor);
  out.bending_warp_Nm *= factor;
  out.bending_weft_Nm *= factor;
  return out;
}

std::vector<int> WarpRow(const FabricModel& model, int i_u) {
  std::vector<int> row;
  for (int j = 0; j < model.mesh.particles_weft(); ++j) row.push_back(model.mesh.Index(i_u, j));
  return row;
}

int RunToRest(FabricStepper* stepper, FabricState* state, int max_steps, double speed_tol) {
  int calm = 0;
  for (int s = 1; s <= max_steps; ++s) {
    stepper->Step(state);
    calm = MaxSpeed(*state) < speed_tol ? calm + 1 : 0;
    if (calm >= 5) return s;
  }
  return max_steps;
}

double AnalyticHangingElongation(const StrainCurve& curve, double length_m, double width_m, double rho, double load_N,
                                 double g) {
  // Strain at tension f (N/m): invert the monotone curve by bisection.
  auto strain_at = [&](double f) {
    double lo = 0.0, hi = 1.0;
    while (curve.Value(hi) < f) hi *= 2.0;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (curve.Value(mid) < f ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  // Composite Simpson over the rest length s (measured from the bottom).
  const int n = 2000;
  const double h = length_m / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double s = i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * strain_at((load_N + rho * g * width_m * s) / width_m);
  }
  return sum * h / 3.0;
}

void Perturb(FabricState* s, double dx_m, double dv_m_per_s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (Eigen::Index i = 0; i < s->x_W_m.size(); ++i) {
    s->x_W_m[i] += dx_m * uniform(rng);
    s->v_W_m_per_s[i] = dv_m_per_s * uniform(rng);
  }
}

}  // namespace haptex::textile::validation
