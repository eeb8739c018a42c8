#include "libs/textile/fabric_stepper.h"

#include <algorithm>
#include <cmath>

#include "libs/base/demand.h"
#include "libs/textile/fabric_strain.h"
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

// The implicit step as sub-steps of dt_s / 2^level: a sub-step whose Newton iterations do not
// converge, or whose largest strain rises beyond the bound, or that is not finite, is retaken
// from its start at half the size while halvings remain; the rest of the step keeps the size
// that worked (a cloth in trouble now stays in trouble for the step). Anchors keep their
// end-of-step positions in every sub-step.
//
// BDF2 takes the whole step as implicit Euler's of 2/3 dt from the extrapolated state; its
// sub-steps after a split are implicit Euler's (first order for that step only: the history
// is the step's start, whatever its sub-steps).
void FabricStepper::StepImplicit(FabricState* state, StepResult* result) {
  const bool strain_bound = options_.max_strain_rise_per_step > 0.0;
  const bool bdf2 = options_.method == Integrator::kBdf2;
  // BDF2's first step (or after a restart) is implicit Euler's, with this state as its history
  const bool has_past = bdf2 && ws_.has_history;
  if (bdf2 && !has_past) {
    ws_.x_previous = state->x_W_m;
    ws_.v_previous = state->v_W_m_per_s;
  }
  if (has_past) RestartMovedParticles(*state);
  StepOptions sub = options_;
  int level = 0;
  std::int64_t sub_steps = 1, done = 0;
  int newton_iterations = 0, cg_iterations = 0;
  result->newton_converged = true;
  while (done < sub_steps) {
    sub.dt_s = options_.dt_s / static_cast<double>(sub_steps);
    const bool second_order = has_past && level == 0;
    const bool may_split = level < options_.max_step_halvings;
    if (may_split) {
      ws_.x_substep_start = state->x_W_m;
      ws_.v_substep_start = state->v_W_m_per_s;
    }
    const double strain_before = strain_bound ? LargestTensileStrain(model_, state->x_W_m) : 0.0;
    const double t_start = state->time_s;
    if (second_order) {
      ExtrapolateBdf2(state);
      sub.dt_s = 2.0 / 3.0 * options_.dt_s;
    }
    const ImplicitStepReport report = ImplicitEulerStep(model_, sub, state, &ws_);
    if (second_order) state->time_s = t_start + options_.dt_s;
    newton_iterations += report.newton_iterations;
    cg_iterations += report.cg.iterations;
    const bool finite = report.cg.finite && ws_.stepped_state_finite;
    const bool strain_ok =
        !strain_bound || !finite ||
        LargestTensileStrain(model_, state->x_W_m) - strain_before <= options_.max_strain_rise_per_step;
    if (may_split && !(finite && report.newton_converged && strain_ok)) {
      state->x_W_m = ws_.x_substep_start;
      state->v_W_m_per_s = ws_.v_substep_start;
      state->time_s = t_start;
      ++level;
      sub_steps *= 2;
      done *= 2;
      ++state->diagnostics.step_halvings;
      continue;
    }
    result->cg = report.cg;
    result->newton_relative_residual = report.newton_relative_residual;
    if (!report.newton_converged) result->newton_converged = false;
    if (!finite) break;  // Step() rolls the whole step back
    ++done;
  }
  result->cg.iterations = cg_iterations;
  result->newton_iterations = newton_iterations;
  result->step_halvings = level;
  last_substeps_ = static_cast<int>(sub_steps);
  FabricDiagnostics& d = state->diagnostics;
  d.last_cg_iterations = cg_iterations;
  d.last_cg_relative_residual = result->cg.relative_residual;
  d.last_newton_iterations = newton_iterations;
  d.last_newton_relative_residual = result->newton_relative_residual;
  if (result->cg.preconditioner_fallback) ++d.preconditioner_fallbacks;
  if (!result->newton_converged) ++d.newton_not_converged;
  if (result->cg.finite && !result->cg.converged) {
    result->status = StepStatus::kCgNotConverged;
    ++d.cg_not_converged;
  }
}

void FabricStepper::RestartMovedParticles(const FabricState& state) {
  const double h = options_.dt_s;
  for (int p = 0; p < model_.num_particles; ++p) {
    const auto x = state.x_W_m.segment<3>(3 * p);
    const auto v = state.v_W_m_per_s.segment<3>(3 * p);
    if (x == ws_.x_left.segment<3>(3 * p) && v == ws_.v_left.segment<3>(3 * p)) continue;
    ws_.x_previous.segment<3>(3 * p) = x - h * v;
    ws_.v_previous.segment<3>(3 * p) = v;
  }
}

void FabricStepper::ExtrapolateBdf2(FabricState* state) {
  const double h = options_.dt_s;
  for (int p = 0; p < model_.num_particles; ++p) {
    auto x = state->x_W_m.segment<3>(3 * p);
    auto v = state->v_W_m_per_s.segment<3>(3 * p);
    auto x_previous = ws_.x_previous.segment<3>(3 * p);
    auto v_previous = ws_.v_previous.segment<3>(3 * p);
    const Eigen::Vector3d x_now = x, v_now = v;
    if (state->mode[static_cast<std::size_t>(p)] == ParticleMode::kFree) {
      x = (4.0 * x_now - x_previous) / 3.0;
      v = (4.0 * v_now - v_previous) / 3.0;
    } else {
      // 2/3 h at the prescribed velocity from here ends where a whole h from the start does
      x = x_now + (h / 3.0) * state->prescribed_v_W_m_per_s.segment<3>(3 * p);
    }
    x_previous = x_now;  // the next step's history: this step's start
    v_previous = v_now;
  }
}

StepResult FabricStepper::Step(FabricState* state) {
  HAPTEX_DEMAND(state->num_particles() == model_.num_particles);
  StepResult result;
  ws_.x_backup = state->x_W_m;  // v rolls back to rest
  const double t0 = state->time_s;
  const bool implicit = options_.method != Integrator::kSymplecticEuler;
  if (implicit) {
    StepImplicit(state, &result);
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
    ws_.has_history = false;  // the cloth restarts at rest
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
  if (options_.method == Integrator::kBdf2) {
    ws_.x_left = state->x_W_m;
    ws_.v_left = state->v_W_m_per_s;
    ws_.has_history = true;
  }
  return result;
}

}  // namespace haptex::textile
