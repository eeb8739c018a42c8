#include "libs/contact/haptic_step_options.h"

namespace haptex::contact {

textile::StepOptions HapticPatchStepOptions(double dt_s) {
  textile::StepOptions step;
  step.method = textile::Integrator::kImplicitEuler;
  step.dt_s = dt_s;
  step.cg_tolerance = 1e-2;
  step.cg_max_iterations = 6;
  step.cg_warm_start = true;
  step.preconditioner = textile::Preconditioner::kGaussSeidel;
  step.ssor_omega = 1.6;
  // The haptic tick has a deadline: a split would multiply its cost; the global step guards the
  // cloth, and the patch's strain changes little in 1 ms.
  step.max_step_halvings = 0;
  return step;
}

}  // namespace haptex::contact
