#pragma once
// Semi-implicit (symplectic) Euler with substeps: the cheap end of the speed/accuracy trade.
// Conditionally stable, so the substep count comes from a stability estimate.

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_workspace.h"
#include "libs/textile/step_options.h"

namespace haptex::textile {

/// Conservative stable explicit step [s]: Gershgorin bound of M^-1 K with the steepest slope of
/// each material curve, reduced for stiffness-proportional damping, times a 0.9 safety factor.
double EstimateExplicitStableStep(const FabricModel& model);

/// Substeps to use for `options`: `options.substeps`, or the fewest allowed by the estimate when
/// it is 0. @throws std::invalid_argument if the given substeps are too few for stability or the
/// required count exceeds `options.max_substeps` (the message says how many are needed).
int SymplecticSubsteps(const FabricModel& model, const StepOptions& options);

/// One step of dt = options.dt_s as `substeps` symplectic Euler substeps: v += h M^-1 f(x, v),
/// x += h v; prescribed particles move with their prescribed velocity. Never allocates.
void SymplecticEulerStep(const FabricModel& model, const StepOptions& options, int substeps,
                         FabricState* state, FabricWorkspace* ws);

}  // namespace haptex::textile
