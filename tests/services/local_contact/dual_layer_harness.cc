#include "tests/services/local_contact/dual_layer_harness.h"

#include <algorithm>
#include <cmath>

#include "services/global_sim/patch_merge.h"
#include "services/local_contact/patch_data.h"
#include "tests/contact/contact_test_util.h"

namespace haptex::local_contact::testing {

Strip PinchStretchStrip(const textile::FabricMaterial& material, double spacing_m) {
  const double width = 0.03, length = 0.08;
  const int nu = static_cast<int>(std::lround(length / spacing_m)) + 1;
  const int nv = static_cast<int>(std::lround(width / spacing_m)) + 1;
  Strip s{textile::BuildFabricModel(material, {length, width, nu, nv}), {}};
  textile::Placement placement;
  placement.origin_W = Eigen::Vector3d(-0.5 * width, 0.0, 0.0);
  placement.axis_u_W = Eigen::Vector3d(0, 0, -1);
  placement.axis_v_W = Eigen::Vector3d(1, 0, 0);
  s.state = textile::MakeRestState(s.model, placement);
  for (int j = 0; j < nv; ++j) s.state.Fix(s.model.mesh.Index(0, j));
  return s;
}

std::array<contact::FingerInput, 2> PinchStretchFingers(double t, const contact::ContactOptions& o) {
  const double r = o.thumb.radius_m + o.fabric_half_thickness_m;
  const double y = r + 0.003 - std::min(1.0, t / 0.3) * 0.0055;
  const double dz = 0.003 * std::clamp((t - 0.5) / 1.5, 0.0, 1.0);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  return {contact::FingerInput{true, contact::testing::PoseFacing(Eigen::Vector3d(0, -y, -0.06 - dz),
                                                                  Eigen::Vector3d(0, 1, 0), x)},
          contact::FingerInput{true, contact::testing::PoseFacing(Eigen::Vector3d(0, y, -0.06 - dz),
                                                                  Eigen::Vector3d(0, -1, 0), x)}};
}

DualLayerHarness::DualLayerHarness(const textile::FabricMaterial& material,
                                   textile::FabricModel global_model,
                                   textile::FabricState global_state, double global_dt_s,
                                   double local_dt_s, const contact::ContactOptions& contact,
                                   double patch_margin_m, int refinement_levels)
    : material_(material),
      global_model_(std::move(global_model)),
      global_state_(std::move(global_state)),
      global_stepper_(global_model_, [&] {
        textile::StepOptions o;
        o.dt_s = global_dt_s;
        o.cg_tolerance = 1e-4;
        return o;
      }()),
      global_dt_s_(global_dt_s),
      local_dt_s_(local_dt_s),
      contact_(contact),
      margin_m_(patch_margin_m),
      refined_(services::MakeRefinedGrid(global_model_.mesh.particles_warp(), global_model_.mesh.particles_weft(),
                                         refinement_levels)),
      ticks_per_global_(static_cast<int>(std::lround(global_dt_s / local_dt_s))) {
  merged_.reserve(static_cast<std::size_t>(global_model_.num_particles));
}

void DualLayerHarness::GlobalStep(const contact::FingerInput& thumb, const contact::FingerInput& index) {
  // Merge the local result as global_sim does (services/global_sim/patch_merge.h): the patch's
  // interior is the local layer's (newer, finer, held by the fingers); it is held where the local
  // layer put it through the global step, the rest of the fabric relaxes against it.
  if (patch_) {
    FillPatchResult(0, patch_.get(), &result_message_);
    global_sim::MergePatchResult(result_message_, static_cast<int>(refined_.id_space()), &global_state_, &merged_);
  }
  global_stepper_.Step(&global_state_);
  global_sim::ReleaseMerged(&global_state_, &merged_);
  const Eigen::VectorXd& cut_v = cut_velocity_.Update(global_state_.v_W_m_per_s);

  const double reach = contact_.thumb.radius_m + 0.5 * contact_.thumb.length_m + contact_.fabric_half_thickness_m;
  std::array<global_sim::FingerSphere, 2> spheres{};
  const std::array<const contact::FingerInput*, 2> in{&thumb, &index};
  for (int f = 0; f < 2; ++f) {
    if (!in[static_cast<std::size_t>(f)]->present) continue;
    const Eigen::Vector3d p = in[static_cast<std::size_t>(f)]->pose.p_W_m;
    spheres[static_cast<std::size_t>(f)] = global_sim::SweptSphere(p, p, Eigen::Vector3d::Zero(), reach, global_dt_s_, margin_m_);
  }
  const global_sim::PatchRect rect = global_sim::FindPatchRect(global_model_, global_state_, spheres);
  if (rect.empty()) return;
  rect_ = rect;
  global_sim::FillLocalPatch(global_model_, global_state_, cut_v, rect, ++patch_id_, 0, global_dt_s_, refined_, &patch_message_);
  PatchData data(patch_message_.particle_ids_size());
  if (data.CopyFrom(patch_message_, refined_.id_space()) != PatchData::Copy::kOk) {
    return;
  }
  textile::StepOptions local_step;
  local_step.dt_s = local_dt_s_;
  local_step.cg_tolerance = 1e-3;
  local_step.cg_max_iterations = 100;
  local_step.preconditioner = textile::Preconditioner::kBlockJacobi;
  auto fresh = BuildPatch(data, material_, global_model_.options, local_step, contact_,
                          static_cast<int>(refined_.id_space()));
  if (patch_) {
    if (carry_over_) HandOff(*patch_, fresh.get());
    ++handoffs_;
  }
  patch_ = std::move(fresh);
}

const contact::ContactOutput& DualLayerHarness::Tick(const contact::FingerInput& thumb,
                                                      const contact::FingerInput& index) {
  if (tick_ % ticks_per_global_ == 0) GlobalStep(thumb, index);
  ++tick_;
  if (!patch_) return idle_;
  const contact::ContactOutput& out = patch_->sim->Tick(thumb, index);
  patch_->force_sum_W_N += patch_->sim->solver().particle_force_W_N();
  ++patch_->ticks_since_result;
  return out;
}

}  // namespace haptex::local_contact::testing
