#include "tests/textile/textile_test_util.h"

#include <cmath>
#include <stdexcept>

namespace haptex::textile::testing {

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

void DenseForceAndJacobians(const FabricModel& model, const ForceFn& fn, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& v, Eigen::VectorXd* f, Eigen::MatrixXd* dfdx,
                            Eigen::MatrixXd* dfdv) {
  const int n = model.num_particles;
  std::vector<Eigen::Matrix3d> blocks(static_cast<std::size_t>(model.pattern.num_blocks()));
  Eigen::VectorXd dfdx_v = Eigen::VectorXd::Zero(3 * n);
  auto run = [&](double sx, double sv) {
    for (auto& b : blocks) b.setZero();
    *f = Eigen::VectorXd::Zero(3 * n);
    ForceSink sink;
    sink.force_N = f;
    sink.system = &blocks;
    sink.dx_scale = sx;
    sink.dv_scale = sv;
    sink.dfdx_v = &dfdx_v;
    sink.v = &v;
    fn(model, x, v, &sink);
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    for (int r = 0; r < n; ++r) {
      for (int k = model.pattern.row_start[static_cast<std::size_t>(r)];
           k < model.pattern.row_start[static_cast<std::size_t>(r) + 1]; ++k) {
        dense.block<3, 3>(3 * r, 3 * model.pattern.cols[static_cast<std::size_t>(k)]) =
            blocks[static_cast<std::size_t>(k)];
      }
    }
    return dense;
  };
  *dfdx = run(1.0, 0.0);
  *dfdv = run(0.0, 1.0);
}

Eigen::MatrixXd FiniteDifferenceJacobian(const FabricModel& model, const ForceFn& fn,
                                         const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                         bool wrt_v, double step) {
  const int n3 = 3 * model.num_particles;
  Eigen::MatrixXd jac(n3, n3);
  auto force = [&](const Eigen::VectorXd& xx, const Eigen::VectorXd& vv) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(n3);
    ForceSink sink;
    sink.force_N = &f;
    fn(model, xx, vv, &sink);
    return f;
  };
  for (int i = 0; i < n3; ++i) {
    Eigen::VectorXd xp = x, xm = x, vp = v, vm = v;
    if (wrt_v) {
      vp[i] += step;
      vm[i] -= step;
    } else {
      xp[i] += step;
      xm[i] -= step;
    }
    jac.col(i) = (force(xp, vp) - force(xm, vm)) / (2.0 * step);
  }
  return jac;
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

double AnalyticHangingElongation(const StrainCurve& curve, double length_m, double width_m,
                                 double rho, double load_N, double g) {
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

}  // namespace haptex::textile::testing
