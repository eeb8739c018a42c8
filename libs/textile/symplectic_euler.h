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

/// Stable explicit step [s] at `state`: a block-Gershgorin bound of M^-1 K (spectral norm of each
/// 3x3 block, so it does not depend on the fabric's orientation) with each element's tangent
/// stiffness at its current deformation (tensile slope at the current strain and the tension
/// |sigma| / |U| across the fibre, shear slope with the current |U|, |V| and the shear force's own
/// geometric term), over free particles only. Tension raises the stiffness above the configuration
/// estimate (a stretched fabric's shear stiffness grows with |U| |V|), so the stepper takes the
/// smaller of the two each step. `row` is scratch (resized to n if needed; no allocation when
/// already sized).
double EstimateExplicitStableStep(const FabricModel& model, const FabricState& state, Eigen::VectorXd* row);

/// Substeps to use for `options`: `options.substeps`, or the fewest allowed by the estimate when
/// it is 0. @throws std::invalid_argument if the given substeps are too few for stability or the
/// required count exceeds `options.max_substeps` (the message says how many are needed).
int SymplecticSubsteps(const FabricModel& model, const StepOptions& options);

/// One step of dt = options.dt_s as `substeps` symplectic Euler substeps: v += h M^-1 f(x, v),
/// x += h v; prescribed particles move with their prescribed velocity. Never allocates.
void SymplecticEulerStep(const FabricModel& model, const StepOptions& options, int substeps, FabricState* state,
                         FabricWorkspace* ws);

}  // namespace haptex::textile
