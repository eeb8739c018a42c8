#include "libs/contact/patch_simulation.h"

#include <utility>

namespace haptex::contact {

PatchSimulation::PatchSimulation(textile::FabricModel model, textile::FabricState state,
                                 const textile::StepOptions& step_options, const ContactOptions& contact_options,
                                 const Eigen::Vector2d& uv_origin_m)
    : model_(std::make_unique<textile::FabricModel>(std::move(model))),
      state_(std::move(state)),
      stepper_(*model_, step_options),
      solver_(*model_, contact_options, uv_origin_m) {
  if (state_.anchor_stiffness_N_per_m.size() != model_->num_particles) {
    state_.anchor_stiffness_N_per_m = Eigen::VectorXd::Zero(model_->num_particles);
    state_.anchor_W_m = state_.x_W_m;
  }
}

const ContactOutput& PatchSimulation::Tick(const FingerInput& thumb, const FingerInput& index) {
  solver_.Prepare(thumb, index, stepper_.options().dt_s, &state_);
  last_step_ = stepper_.Step(&state_);
  return solver_.Resolve(state_);
}

}  // namespace haptex::contact
