#pragma once
// Mutable simulation state of one fabric: positions, velocities, applied loads, constraints and
// diagnostics counters (MuJoCo's mjData, in spirit). Plain data: copy it to save or restore.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"

namespace haptex::textile {

/// How a particle moves.
enum class ParticleMode : std::uint8_t {
  kFree = 0,        ///< integrated
  kPrescribed = 1,  ///< moves with prescribed_velocity (zero: fixed to the stand)
};

/// Counters of numerical trouble; they only grow (reset by the owner).
struct FabricDiagnostics {
  std::int64_t steps = 0;
  std::int64_t nan_events = 0;                ///< steps rolled back because of NaN/Inf
  std::int64_t cg_not_converged = 0;          ///< steps whose CG hit max iterations
  std::int64_t speed_capped = 0;              ///< particle speeds clamped to the cap
  std::int64_t preconditioner_fallbacks = 0;  ///< multilevel PCG broke down, block Jacobi used
  /// Symplectic steps whose stability estimate at the state wanted more than max_substeps (the
  /// step used max_substeps).
  std::int64_t substeps_limited = 0;
  /// Implicit steps kept with Newton above its tolerance (no halving left, or none allowed).
  std::int64_t newton_not_converged = 0;
  /// Implicit sub-steps retaken as two halves (Newton did not converge, strain bound, NaN).
  std::int64_t step_halvings = 0;
  int last_cg_iterations = 0;  ///< of the whole last step (every Newton iteration and sub-step)
  double last_cg_relative_residual = 0.0;
  int last_newton_iterations = 0;  ///< linear solves of the last step
  double last_newton_relative_residual = 0.0;
};

/// Rest placement in the world: x = origin + u axis_u + v axis_v.
struct Placement {
  Eigen::Vector3d origin_W{0.0, 0.0, 0.0};
  Eigen::Vector3d axis_u_W{1.0, 0.0, 0.0};  ///< the grid's u direction (the warp at material angle 0), unit
  Eigen::Vector3d axis_v_W{0.0, 1.0, 0.0};  ///< the grid's v direction (the weft at material angle 0), unit
};

struct FabricState {
  double time_s = 0.0;
  Eigen::VectorXd x_W_m;                   ///< 3n positions, world frame
  Eigen::VectorXd v_W_m_per_s;             ///< 3n velocities
  Eigen::VectorXd external_force_W_N;      ///< 3n applied loads (point/edge), kept until changed
  std::vector<ParticleMode> mode;          ///< n
  Eigen::VectorXd prescribed_v_W_m_per_s;  ///< 3n, used where mode == kPrescribed
  /// Springs from particles to moving anchors (finger contact): f_p = k_p (anchor_p - x_p),
  /// integrated implicitly by both integrators so stiff contact stays stable. k_p = 0: none.
  Eigen::VectorXd anchor_stiffness_N_per_m;  ///< n
  Eigen::VectorXd anchor_W_m;                ///< 3n, where each anchor is at the end of the step
  FabricDiagnostics diagnostics;

  int num_particles() const { return static_cast<int>(mode.size()); }
  Eigen::Ref<Eigen::Vector3d> x(int p) { return x_W_m.segment<3>(3 * p); }
  Eigen::Vector3d x(int p) const { return x_W_m.segment<3>(3 * p); }
  Eigen::Ref<Eigen::Vector3d> v(int p) { return v_W_m_per_s.segment<3>(3 * p); }
  Eigen::Vector3d v(int p) const { return v_W_m_per_s.segment<3>(3 * p); }

  /// Fixes particle p in place (the stand).
  void Fix(int p);
  /// Moves particle p with constant velocity (local patch borders, tests).
  void Prescribe(int p, const Eigen::Vector3d& v_W_m_per_s);
  void Free(int p);
  /// Removes every anchor spring.
  void ClearAnchors();
};

/// The rest configuration at rest, every particle free, no loads.
/// @throws std::invalid_argument if the placement axes are not orthonormal.
FabricState MakeRestState(const FabricModel& model, const Placement& placement = {});

/// Kinetic energy [J].
double KineticEnergy(const FabricModel& model, const FabricState& state);
/// Largest particle speed [m/s].
double MaxSpeed(const FabricState& state);

}  // namespace haptex::textile
