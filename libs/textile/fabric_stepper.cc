#include "libs/textile/fabric_stepper.h"

#include <algorithm>
#include <cmath>

#include "libs/base/demand.h"
#include "libs/textile/symplectic_euler.h"

namespace haptex::textile {

const char* ToString(StepStatus status) {
  switch (status) {
    case StepStatus::kOk:
      return "ok";
    case StepStatus::kCgNotConverged:
      return "cg_not_converged";
    case StepStatus::kSpeedCapped:
      return "speed_capped";
    case StepStatus::kNanRecovered:
      return "nan_recovered";
  }
  return "unknown";
}

FabricStepper::FabricStepper(const FabricModel& model, const StepOptions& options)
    : model_(model), options_(options), ws_(model, options.preconditioner) {
  ValidateStepOptions(options_);
  if (options_.method == Integrator::kSymplecticEuler) {
    substeps_ = SymplecticSubsteps(model_, options_);
    config_stable_step_s_ = EstimateExplicitStableStep(model_);
  }
  last_substeps_ = substeps_;
}

StepResult FabricStepper::Step(FabricState* state) {
  HAPTEX_DEMAND(state->num_particles() == model_.num_particles);
  StepResult result;
  ws_.x_backup = state->x_W_m;  // v rolls back to rest
  const double t0 = state->time_s;
  const bool implicit = options_.method == Integrator::kImplicitEuler;
  if (implicit) {
    result.cg = ImplicitEulerStep(model_, options_, state, &ws_);
    state->diagnostics.last_cg_iterations = result.cg.iterations;
    state->diagnostics.last_cg_relative_residual = result.cg.relative_residual;
    if (result.cg.preconditioner_fallback) ++state->diagnostics.preconditioner_fallbacks;
    if (result.cg.finite && !result.cg.converged) {
      result.status = StepStatus::kCgNotConverged;
      ++state->diagnostics.cg_not_converged;
    }
  } else {
    // Substeps for the tension at this state (never fewer than configured).
    const double stable =
        std::min(config_stable_step_s_, EstimateExplicitStableStep(model_, *state, &ws_.stiffness_row));
    const double needed = std::ceil(options_.dt_s / stable);
    int substeps = substeps_;
    if (needed > substeps) {
      if (needed > options_.max_substeps) {
        substeps = options_.max_substeps;
        ++state->diagnostics.substeps_limited;
      } else {
        substeps = static_cast<int>(needed);
      }
    }
    last_substeps_ = substeps;
    SymplecticEulerStep(model_, options_, substeps, state, &ws_);
  }
  ++state->diagnostics.steps;

  // NaN/Inf: roll back to the last good positions, at rest. A finite implicit step checked
  // the state it wrote.
  const bool state_finite =
      implicit ? ws_.stepped_state_finite : state->x_W_m.allFinite() && state->v_W_m_per_s.allFinite();
  if (!result.cg.finite || !state_finite) {
    state->x_W_m = ws_.x_backup;
    state->v_W_m_per_s.setZero();
    state->time_s = t0 + options_.dt_s;
    ++state->diagnostics.nan_events;
    result.status = StepStatus::kNanRecovered;
    return result;
  }
  // Speed cap: keep the direction, count the event.
  const double cap = options_.max_speed_m_per_s;
  const bool may_cap = !implicit || ws_.stepped_max_speed2_m2_per_s2 > cap * cap;
  for (int p = 0; may_cap && p < model_.num_particles; ++p) {
    auto v = state->v_W_m_per_s.segment<3>(3 * p);
    if (v.squaredNorm() > cap * cap) {  // the square root only where it caps
      v *= cap / v.norm();
      ++result.capped_particles;
    }
  }
  if (result.capped_particles > 0) {
    ++state->diagnostics.speed_capped;
    result.status = StepStatus::kSpeedCapped;
  }
  return result;
}

}  // namespace haptex::textile
