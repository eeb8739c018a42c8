#include "libs/textile/fabric_energy.h"

#include <array>

#include "libs/textile/fabric_strain.h"

namespace haptex::textile {
namespace {

// Gauss-Legendre with 4 points on [a, b]: exact for the cubic pieces of the laws.
double Integrate4(const StrainCurve& curve, double a, double b) {
  static constexpr std::array<double, 2> kNode = {0.3399810435848563, 0.8611363115940526};
  static constexpr std::array<double, 2> kWeight = {0.6521451548625461, 0.3478548451374538};
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double sum = 0.0;
  for (std::size_t k = 0; k < kNode.size(); ++k) {
    sum += kWeight[k] * (curve.Value(mid - half * kNode[k]) + curve.Value(mid + half * kNode[k]));
  }
  return half * sum;
}

// Integral of the law from 0 to `strain` [N/m], piece by piece between the spline's knots
// (the compression branch and the extrapolation beyond the data are linear, the odd law's
// negative side mirrors the positive one).
double CurveEnergyPerArea(const StrainCurve& curve, double strain) {
  if (strain == 0.0) return 0.0;
  if (strain < 0.0) {
    if (curve.odd()) return CurveEnergyPerArea(curve, -strain);
    return -Integrate4(curve, strain, 0.0);  // the linear compression branch
  }
  double energy = 0.0, from = 0.0;
  for (const double knot : curve.loading().knots_x()) {
    if (knot <= from) continue;
    if (knot >= strain) break;
    energy += Integrate4(curve, from, knot);
    from = knot;
  }
  return energy + Integrate4(curve, from, strain);
}

}  // namespace

double PotentialEnergy(const FabricModel& model, const FabricState& state) {
  const Eigen::VectorXd& x = state.x_W_m;
  double energy_J = 0.0;
  for (const TriangleElement& e : model.triangles) {
    Eigen::Vector3d u, v;
    YarnVectors(e, x, &u, &v);
    energy_J += e.area_m2 * (CurveEnergyPerArea(model.material.tensile_warp, u.norm() - 1.0) +
                             CurveEnergyPerArea(model.material.tensile_weft, v.norm() - 1.0) +
                             CurveEnergyPerArea(model.material.shear, u.dot(v)));
  }
  for (const BendElement& e : model.bends) {
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < 3; ++k) r += e.alpha[k] * x.segment<3>(3 * e.p[k]);
    energy_J += 0.5 * e.lambda_N_per_m * r.squaredNorm();
  }
  for (int p = 0; p < model.num_particles; ++p) {
    energy_J -= model.mass_kg[p] * model.options.gravity_m_per_s2.dot(x.segment<3>(3 * p));
    const double k = state.anchor_stiffness_N_per_m[p];
    if (k > 0.0) energy_J += 0.5 * k * (state.anchor_W_m.segment<3>(3 * p) - x.segment<3>(3 * p)).squaredNorm();
  }
  return energy_J;
}

double TotalEnergy(const FabricModel& model, const FabricState& state) {
  return KineticEnergy(model, state) + PotentialEnergy(model, state);
}

}  // namespace haptex::textile
