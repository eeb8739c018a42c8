#pragma once
// Where element forces and Jacobians go: the force vector, and optionally the implicit system
// matrix A = M + dv_scale df/dv + dx_scale df/dx and the product (df/dx) v.

#include <vector>

#include <Eigen/Core>

namespace haptex::textile {

struct ForceSink {
  Eigen::VectorXd* force_N = nullptr;              ///< 3n, accumulated
  std::vector<Eigen::Matrix3d>* system = nullptr;  ///< null: forces only
  double dx_scale = 0.0;                           ///< -h^2 for implicit Euler
  double dv_scale = 0.0;                           ///< -h
  Eigen::VectorXd* dfdx_v = nullptr;               ///< 3n, accumulated (df/dx) v
  const Eigen::VectorXd* v = nullptr;              ///< 3n velocities
  /// AccumulateForces only: the constant Jacobian blocks (bending, linear drag) are already in
  /// `system` (AddConstantJacobians), so it adds only the state-dependent ones.
  bool constant_jacobians_added = false;
  /// AccumulateForces only: when set (blocks like `system`), the triangle kernel's first
  /// addition to each block (FabricModel::triangle_first_blocks) is to this block instead of
  /// `system`'s, stored in `system`: the caller need not reset the blocks triangles touch.
  const Eigen::Matrix3d* system_base = nullptr;

  bool wants_jacobians() const { return system != nullptr; }

  void AddForce(int p, const Eigen::Vector3d& f) { force_N->segment<3>(3 * p) += f; }
  /// Block d f_i / d x_j at `slot`.
  void AddDx(int slot, int i, int j, const Eigen::Matrix3d& jac) {
    (*system)[static_cast<std::size_t>(slot)] += dx_scale * jac;
    dfdx_v->segment<3>(3 * i) += jac * v->segment<3>(3 * j);
  }
  /// Block d f_i / d v_j at `slot`.
  void AddDv(int slot, const Eigen::Matrix3d& jac) { (*system)[static_cast<std::size_t>(slot)] += dv_scale * jac; }
};

}  // namespace haptex::textile
