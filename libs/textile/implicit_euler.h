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

/// Solves (M - h df/dv - h^2 df/dx) dv = h (f + h df/dx v) for free particles; prescribed
/// particles get exactly their prescribed velocity (filtered CG). Then v += dv, x += h v.
/// Does not validate options (FabricStepper does) and never allocates.
CgReport ImplicitEulerStep(const FabricModel& model, const StepOptions& options, FabricState* state,
                           FabricWorkspace* ws);

}  // namespace haptex::textile
