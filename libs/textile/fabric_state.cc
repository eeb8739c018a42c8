#include "libs/textile/fabric_state.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace haptex::textile {

void FabricState::Fix(int p) { Prescribe(p, Eigen::Vector3d::Zero()); }

void FabricState::Prescribe(int p, const Eigen::Vector3d& v) {
  mode[static_cast<std::size_t>(p)] = ParticleMode::kPrescribed;
  prescribed_v_W_m_per_s.segment<3>(3 * p) = v;
  v_W_m_per_s.segment<3>(3 * p) = v;
}

void FabricState::Free(int p) { mode[static_cast<std::size_t>(p)] = ParticleMode::kFree; }

void FabricState::ClearAnchors() {
  anchor_stiffness_N_per_m.setZero();
  anchor_W_m = x_W_m;
}

FabricState MakeRestState(const FabricModel& model, const Placement& placement) {
  const double tol = 1e-9;
  if (std::abs(placement.axis_u_W.norm() - 1.0) > tol || std::abs(placement.axis_v_W.norm() - 1.0) > tol ||
      std::abs(placement.axis_u_W.dot(placement.axis_v_W)) > tol || !placement.origin_W.allFinite()) {
    throw std::invalid_argument("Placement: axis_u_W and axis_v_W must be orthonormal, origin finite");
  }
  const int n = model.num_particles;
  FabricState s;
  s.x_W_m.resize(3 * n);
  for (int p = 0; p < n; ++p) {
    const Eigen::Vector2d& uv = model.mesh.rest_uv_m(p);
    s.x_W_m.segment<3>(3 * p) = placement.origin_W + uv.x() * placement.axis_u_W + uv.y() * placement.axis_v_W;
  }
  s.v_W_m_per_s = Eigen::VectorXd::Zero(3 * n);
  s.external_force_W_N = Eigen::VectorXd::Zero(3 * n);
  s.mode.assign(static_cast<std::size_t>(n), ParticleMode::kFree);
  s.prescribed_v_W_m_per_s = Eigen::VectorXd::Zero(3 * n);
  s.anchor_stiffness_N_per_m = Eigen::VectorXd::Zero(n);
  s.anchor_W_m = s.x_W_m;
  return s;
}

double KineticEnergy(const FabricModel& model, const FabricState& state) {
  double e = 0.0;
  for (int p = 0; p < model.num_particles; ++p) {
    e += 0.5 * model.mass_kg[p] * state.v_W_m_per_s.segment<3>(3 * p).squaredNorm();
  }
  return e;
}

double MaxSpeed(const FabricState& state) {
  double m = 0.0;
  for (int p = 0; p < state.num_particles(); ++p) {
    m = std::max(m, state.v_W_m_per_s.segment<3>(3 * p).norm());
  }
  return m;
}

}  // namespace haptex::textile
