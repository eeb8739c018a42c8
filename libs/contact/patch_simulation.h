#pragma once
// A fabric patch and the fingers on it, advanced one haptic tick at a time: contact springs from
// ContactSolver, one fabric step (libs/textile, springs implicit), then forces and friction.
// The in-process harness of the contact tests, the local_contact service's core, and the
// single-layer reference of the dual-layer tests.

#include <memory>

#include "libs/contact/contact_solver.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/step_options.h"

namespace haptex::contact {

class PatchSimulation {
 public:
  /// Takes the patch's model and initial state (prescribed particles stay prescribed).
  /// @throws std::invalid_argument for invalid step or contact options.
  PatchSimulation(textile::FabricModel model, textile::FabricState state, const textile::StepOptions& step_options,
                  const ContactOptions& contact_options, const Eigen::Vector2d& uv_origin_m = Eigen::Vector2d::Zero());
  PatchSimulation(const PatchSimulation&) = delete;
  PatchSimulation& operator=(const PatchSimulation&) = delete;

  /// One tick of step_options.dt_s, the fingers' poses given for the tick's end. Never allocates.
  const ContactOutput& Tick(const FingerInput& thumb, const FingerInput& index);

  const textile::FabricModel& model() const { return *model_; }
  textile::FabricState& state() { return state_; }
  const textile::FabricState& state() const { return state_; }
  ContactSolver& solver() { return solver_; }
  const textile::StepResult& last_step() const { return last_step_; }
  double dt_s() const { return stepper_.options().dt_s; }

 private:
  std::unique_ptr<textile::FabricModel> model_;  // stable address: stepper and solver refer to it
  textile::FabricState state_;
  textile::FabricStepper stepper_;
  ContactSolver solver_;
  textile::StepResult last_step_;
};

}  // namespace haptex::contact
