#pragma once
// Implicit (backward) Euler with one Newton step and constraint-filtered preconditioned CG
// (Baraff & Witkin 1998, docs/physics-reference.md section 5).

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_workspace.h"
#include "libs/textile/step_options.h"

namespace haptex::textile {

struct CgReport {
  int iterations = 0;
  double relative_residual = 0.0;  ///< sqrt(r'P^-1 r / b'P^-1 b) at exit
  bool converged = true;
  bool finite = true;                    ///< false: NaN/Inf in the system; the state was left untouched
  bool preconditioner_fallback = false;  ///< multilevel broke down; solved with block Jacobi
};

/// One implicit step's linear solves and Newton iterations.
struct ImplicitStepReport {
  /// The solves together: iterations summed, the last one's residual, converged only if all did,
  /// finite false when one was not (the state then is partly stepped: the caller rolls back).
  CgReport cg;
  int newton_iterations = 0;              ///< linear solves taken (1: Baraff-Witkin's step)
  double newton_relative_residual = 0.0;  ///< |g| / force level at exit; 0 when not measured (1 iteration)
  bool newton_converged = true;           ///< false: newton_max_iterations reached above the tolerance
};

/// Solves (M - h df/dv - h^2 df/dx) dv = h (f + h df/dx v) for free particles; prescribed
/// particles get exactly their prescribed velocity (filtered CG). Then v += dv, x += h v. With
/// options.newton_max_iterations > 1, Newton corrections follow until the residual impulse meets
/// options.newton_tolerance (step_options.h). Does not validate options (FabricStepper does)
/// and never allocates.
ImplicitStepReport ImplicitEulerStep(const FabricModel& model, const StepOptions& options, FabricState* state,
                                     FabricWorkspace* ws);

}  // namespace haptex::textile
