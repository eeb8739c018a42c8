#include "libs/dual_layer/dual_layer_sim.h"

#include <cmath>

namespace haptex::dual_layer {

DualLayerSim::DualLayerSim(const textile::FabricMaterial& material, textile::FabricModel global_model,
                           textile::FabricState global_state, double global_dt_s, double local_dt_s,
                           const contact::ContactOptions& contact, double patch_margin_m, int refinement_levels)
    : material_(material),
      global_model_(std::move(global_model)),
      global_state_(std::move(global_state)),
      global_stepper_(global_model_,
                      [&] {
                        textile::StepOptions o;
                        o.dt_s = global_dt_s;
                        o.cg_tolerance = 1e-4;
                        return o;
                      }()),
      global_dt_s_(global_dt_s),
      local_dt_s_(local_dt_s),
      contact_(contact),
      margin_m_(patch_margin_m),
      refined_(
          MakeRefinedGrid(global_model_.mesh.particles_warp(), global_model_.mesh.particles_weft(), refinement_levels)),
      ticks_per_global_(static_cast<int>(std::lround(global_dt_s / local_dt_s))) {
  merged_ = MergedInterior(static_cast<int>(std::ceil(kLastResultHoldMax_s / global_dt_s - 1e-9)),
                           global_model_.num_particles);
}

void DualLayerSim::GlobalStep(const contact::FingerInput& thumb, const contact::FingerInput& index) {
  // Merge the local result as global_sim does: the patch's interior is the local layer's (newer,
  // finer, held by the fingers); it is held where the local layer put it through the global step,
  // the rest of the fabric relaxes against it. Results (and patches) travel link_delay_steps_
  // global steps.
  if (patch_) {
    results_in_flight_.emplace_back();
    FillPatchResult(patch_step_, patch_.get(), &results_in_flight_.back());
  }
  if (static_cast<int>(results_in_flight_.size()) > link_delay_steps_) {
    merged_.Merge(results_in_flight_.front(), static_cast<int>(refined_.id_space()), &global_state_);
    link_delay_.OnResultMerged(steps_, results_in_flight_.front().global_step);
    results_in_flight_.pop_front();
  }
  merged_.HoldBeforeStep(&global_state_);
  global_stepper_.Step(&global_state_);
  ++steps_;
  merged_.ReleaseAfterStep(&global_state_);
  const Eigen::VectorXd& cut_v = cut_velocity_.Update(global_state_.v_W_m_per_s);

  const double reach = contact_.thumb.radius_m + 0.5 * contact_.thumb.length_m + contact_.fabric_half_thickness_m;
  std::array<FingerSphere, 2> spheres{};
  const std::array<const contact::FingerInput*, 2> in{&thumb, &index};
  for (int f = 0; f < 2; ++f) {
    if (!in[static_cast<std::size_t>(f)]->present) continue;
    const Eigen::Vector3d p = in[static_cast<std::size_t>(f)]->pose.p_W_m;
    spheres[static_cast<std::size_t>(f)] = SweptSphere(p, p, Eigen::Vector3d::Zero(), reach, global_dt_s_, margin_m_);
  }
  const PatchRect rect = FindPatchRect(global_model_, global_state_, spheres);
  if (rect.empty()) return;
  rect_ = rect;
  CutPatch(global_model_, global_state_, cut_v, rect, ++patch_id_, steps_, global_dt_s_, refined_, &patch_data_);
  patch_data_.link_round_trip_steps = extrapolate_border_in_full_ ? 0 : link_delay_.round_trip_steps();
  if (!IsBuildable(patch_data_, refined_.id_space())) return;
  textile::StepOptions local_step;
  local_step.dt_s = local_dt_s_;
  local_step.cg_tolerance = 1e-3;
  local_step.cg_max_iterations = 100;
  local_step.preconditioner = textile::Preconditioner::kBlockJacobi;
  patches_in_flight_.push_back(BuildLocalPatch(patch_data_, material_, global_model_.options, local_step, contact_,
                                               static_cast<int>(refined_.id_space())));
}

void DualLayerSim::HandOffArrived() {
  if (static_cast<int>(patches_in_flight_.size()) <= link_delay_steps_) return;
  std::unique_ptr<LocalPatch> fresh = std::move(patches_in_flight_.front());
  patches_in_flight_.pop_front();
  if (patch_) {
    if (carry_over_) HandOff(*patch_, fresh.get());
    ++handoffs_;
  }
  patch_step_ = fresh->global_step;
  patch_ = std::move(fresh);
}

const contact::ContactOutput& DualLayerSim::Tick(const contact::FingerInput& thumb, const contact::FingerInput& index) {
  if (tick_ % ticks_per_global_ == 0) {
    GlobalStep(thumb, index);
    HandOffArrived();
  }
  ++tick_;
  if (!patch_) return idle_;
  return patch_->Tick(thumb, index);
}

}  // namespace haptex::dual_layer
