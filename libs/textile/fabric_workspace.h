#pragma once
// Scratch memory of a step, sized once from the model; a warmed-up step allocates nothing.

#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/gauss_seidel_preconditioner.h"
#include "libs/textile/multilevel_preconditioner.h"
#include "libs/textile/padded_vector.h"
#include "libs/textile/step_options.h"

namespace haptex::textile {

struct FabricWorkspace {
  /// Allocates every buffer for `model` (Gauss-Seidel's only for that preconditioner).
  FabricWorkspace(const FabricModel& model, Preconditioner preconditioner);

  Eigen::VectorXd force_N;               ///< 3n total force
  Eigen::VectorXd dfdx_v;                ///< 3n (df/dx) v, for the implicit right-hand side
  std::vector<Eigen::Matrix3d> system;   ///< blocks of M - h df/dv - h^2 df/dx (model.pattern)
  std::vector<Eigen::Matrix3d> precond;  ///< inverted diagonal blocks
  /// Constant part of `system` (mass, bending, linear drag) for step system_base_dt_s of
  /// system_base_model; rebuilt when either changes. A step's triangle kernel starts the blocks
  /// it touches from these (ForceSink::system_base): no step resets `system` whole.
  std::vector<Eigen::Matrix3d> system_base;
  /// Values of the scalar blocks of `system_base` (model.product_rows order): the product reads
  /// them instead of the 3x3 blocks (no step changes them).
  std::vector<double> system_scalars;
  double system_base_dt_s = 0.0;
  const FabricModel* system_base_model = nullptr;
  /// 3n CG vectors. dv0: the initial guess, copied only for block Jacobi and multilevel
  /// (Gauss-Seidel's PCG leaves dv at the guess on a breakdown), so stale on its steps.
  Eigen::VectorXd rhs, dv, dv0, r, c, q, s;
  Eigen::VectorXd x_backup;  ///< roll-back copy of the positions
  /// The velocities at the start of an implicit step: its Newton residual's inertia term.
  Eigen::VectorXd v_step_start;
  /// Where a split step's current sub-step started, to retake it as two halves.
  Eigen::VectorXd x_substep_start, v_substep_start;
  /// BDF2's history: the state at the start of the last step (x_n-1, v_n-1), if it has one, and
  /// the state that step left (a particle that no longer is there was moved by the state's owner).
  Eigen::VectorXd x_previous, v_previous, x_left, v_left;
  bool has_history = false;
  /// Set by ImplicitEulerStep when it updates the state, for FabricStepper's checks (no second
  /// scan): whether the new x and v are all finite, and the largest squared particle speed.
  bool stepped_state_finite = true;
  double stepped_max_speed2_m2_per_s2 = 0.0;
  Eigen::VectorXd stiffness_row;           ///< n, symplectic stability estimate at the state
  MultilevelPreconditioner multilevel;     ///< used when StepOptions::preconditioner says so
  GaussSeidelPreconditioner gauss_seidel;  ///< likewise (empty unless built for it)
  /// Gauss-Seidel's CG vectors on its split system, padded (0 rows unless built for it): the
  /// residual, direction, product, preconditioned residual, the sweeps' scratch t and z, and
  /// the correction y (kept unsplit).
  struct SplitVectors {
    PaddedVector r, c, q, s, t, z, y;
  } split;
};

}  // namespace haptex::textile
