#pragma once
// Advances a fabric by one step with the configured integrator, and reports numerical trouble
// as a status plus counters in FabricState::diagnostics (never a silent blow-up).

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_workspace.h"
#include "libs/textile/implicit_euler.h"
#include "libs/textile/step_options.h"

namespace haptex::textile {

/// Outcome of one step, worst first.
enum class StepStatus {
  kOk = 0,
  kCgNotConverged = 1,  ///< CG stopped at cg_max_iterations; the step was still taken
  kSpeedCapped = 2,     ///< some particle exceeded max_speed_m_per_s and was slowed down
  kNanRecovered = 3,    ///< the step produced NaN/Inf; state rolled back and velocities zeroed
};

const char* ToString(StepStatus status);

struct StepResult {
  StepStatus status = StepStatus::kOk;
  /// Implicit Euler only: the last sub-step's solve, with the iterations of the whole step.
  CgReport cg;
  int newton_iterations = 0;              ///< implicit: linear solves of the whole step, retaken sub-steps' too
  double newton_relative_residual = 0.0;  ///< implicit: the last sub-step's (0: not measured)
  bool newton_converged = true;           ///< false: a sub-step was kept above the tolerance
  int step_halvings = 0;                  ///< implicit: the step ended at dt_s / 2^this
  int capped_particles = 0;
};

/// Owns the workspace for one model and validated options. Step() never allocates or throws.
class FabricStepper {
 public:
  /// @throws std::invalid_argument for invalid options, or a symplectic configuration that the
  /// stability estimate refuses.
  FabricStepper(const FabricModel& model, const StepOptions& options);

  StepResult Step(FabricState* state);

  /// BDF2 steps from the state and the one a step before it, which this stepper keeps. A
  /// particle its owner moved between steps (a patch's result merged, a reset: its position or
  /// velocity is not what the last step left) gets the past of a uniform motion at its present
  /// velocity, for that step first order there. An owner that puts the whole state elsewhere (a
  /// loaded state, another cloth) may call this instead: the next step is implicit Euler's.
  void RestartHistory() { ws_.has_history = false; }

  const StepOptions& options() const { return options_; }
  /// Substeps of the last step (before the first: the configured count; implicit Euler: 1, or
  /// 2^halvings after a split). Each symplectic step uses at least the configured count, more when the
  /// stability estimate at the current state (tension) asks for it, up to max_substeps.
  int substeps() const { return last_substeps_; }

 private:
  void StepImplicit(FabricState* state, StepResult* result);
  /// BDF2: the particles moved since the last step restart their history (RestartHistory).
  void RestartMovedParticles(const FabricState& state);
  /// BDF2: the state becomes the extrapolated start (4 x_n - x_n-1) / 3, (4 v_n - v_n-1) / 3 of
  /// an implicit Euler step of 2/3 dt (prescribed particles: where that step ends on their
  /// path), and the history moves on to x_n, v_n.
  void ExtrapolateBdf2(FabricState* state);

  const FabricModel& model_;
  StepOptions options_;
  int substeps_ = 1;
  int last_substeps_ = 1;
  double config_stable_step_s_ = 0.0;  // EstimateExplicitStableStep(model), symplectic only
  FabricWorkspace ws_;
};

}  // namespace haptex::textile
