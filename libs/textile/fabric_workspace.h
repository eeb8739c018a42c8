#pragma once
// Scratch memory of a step, sized once from the model; a warmed-up step allocates nothing.

#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/gauss_seidel_preconditioner.h"
#include "libs/textile/multilevel_preconditioner.h"
#include "libs/textile/step_options.h"

namespace haptex::textile {

struct FabricWorkspace {
  /// Allocates every buffer for `model` (Gauss-Seidel's only for that preconditioner).
  FabricWorkspace(const FabricModel& model, Preconditioner preconditioner);

  Eigen::VectorXd force_N;        ///< 3n total force
  Eigen::VectorXd dfdx_v;         ///< 3n (df/dx) v, for the implicit right-hand side
  std::vector<Eigen::Matrix3d> system;   ///< blocks of M - h df/dv - h^2 df/dx (model.pattern)
  std::vector<Eigen::Matrix3d> precond;  ///< inverted diagonal blocks
  /// Constant part of `system` (mass, bending, linear drag) for step system_base_dt_s of
  /// system_base_model; rebuilt when either changes.
  std::vector<Eigen::Matrix3d> system_base;
  /// Values of the scalar blocks of `system_base` (model.product_rows order): the product reads
  /// them instead of the 3x3 blocks (no step changes them).
  std::vector<double> system_scalars;
  double system_base_dt_s = 0.0;
  const FabricModel* system_base_model = nullptr;
  Eigen::VectorXd rhs, dv, dv0, r, c, q, s;  ///< 3n CG vectors (dv0: initial guess)
  Eigen::VectorXd t, z, y_split;         ///< 3n, Gauss-Seidel's sweeps and its split unknown
  Eigen::VectorXd x_backup, v_backup;    ///< roll-back copy of the state
  Eigen::VectorXd stiffness_row;         ///< n, symplectic stability estimate at the state
  MultilevelPreconditioner multilevel;   ///< used when StepOptions::preconditioner says so
  GaussSeidelPreconditioner gauss_seidel;  ///< likewise (empty unless built for it)
};

}  // namespace haptex::textile
