#include "services/local_contact/local_contact_codec.h"

#include "libs/codec/message_conversion.h"

namespace haptex::local_contact {

v1::ContactState ToMessage(contact::ContactState state) {
  return static_cast<v1::ContactState>(static_cast<int>(state));
}

std::array<contact::FingerInput, 2> FingerInputs(const v1::FingerStates& states,
                                                 const std::array<bool, 2>& scene_fingers,
                                                 const std::array<bool, 2>& ahead,
                                                 std::array<Eigen::Vector3d, 2>* at_bridge) {
  std::array<contact::FingerInput, 2> fingers{};
  if (!states.device_ok()) return fingers;
  for (const v1::FingerState& f : states.fingers()) {
    const int slot = codec::FingerSlot(f.finger());
    if (slot < 0 || !scene_fingers[static_cast<std::size_t>(slot)]) continue;
    contact::FingerInput& in = fingers[static_cast<std::size_t>(slot)];
    in.present = true;
    Eigen::Vector3d bridge_p_W_m = codec::ToEigen(f.position_w_m());
    Eigen::Vector3d ahead_p_W_m = bridge_p_W_m;
    if (f.has_predicted_position_w_m()) {
      ahead_p_W_m = codec::ToEigen(f.predicted_position_w_m());
      bridge_p_W_m = ahead_p_W_m - f.link_horizon_s() * codec::ToEigen(f.velocity_w_m_per_s());
    }
    in.pose.p_W_m = ahead[static_cast<std::size_t>(slot)] ? ahead_p_W_m : bridge_p_W_m;
    in.pose.R_WF = codec::ToRotation(f.orientation_wf());
    if (at_bridge != nullptr) (*at_bridge)[static_cast<std::size_t>(slot)] = bridge_p_W_m;
  }
  return fingers;
}

void FillForceModel(const contact::ContactOutput* contact, const std::array<contact::FingerInput, 2>& fingers,
                    std::uint64_t based_on_controller_sequence, double ttl_s, v1::ForceModel* out) {
  out->set_based_on_controller_sequence(based_on_controller_sequence);
  while (out->fingers_size() < codec::kFingerSlots) out->add_fingers();
  for (int f = 0; f < codec::kFingerSlots; ++f) {
    v1::FingerForceModel* m = out->mutable_fingers(f);
    m->set_finger(codec::FingerOfSlot(f));
    const contact::FingerInput& in = fingers[static_cast<std::size_t>(f)];
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    Eigen::Matrix3d k = Eigen::Matrix3d::Zero(), k_cross = Eigen::Matrix3d::Zero();
    Eigen::Vector3d cone_axis = Eigen::Vector3d::Zero();
    double cone_mu = 0.0;
    // no contact force, no stiffness: the bridge must not extrapolate a contact that is not there
    const contact::FingerContactOutput* o =
        contact != nullptr ? &contact->finger[static_cast<std::size_t>(f)] : nullptr;
    if (o != nullptr && in.present && !o->force_W_N.isZero(0.0)) {
      force = o->force_W_N;
      k = o->stiffness_W_N_per_m;
      k_cross = o->cross_stiffness_W_N_per_m;
      cone_axis = -o->contact_normal_W;
      cone_mu = o->friction_cone_mu;
    }
    codec::ToMessage(force, m->mutable_f0_w_n());
    codec::ToMessage(in.pose.p_W_m, m->mutable_x0_w_m());
    m->mutable_stiffness_w_n_per_m()->Resize(9, 0.0);
    m->mutable_cross_stiffness_w_n_per_m()->Resize(9, 0.0);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        m->set_stiffness_w_n_per_m(3 * r + c, k(r, c));
        m->set_cross_stiffness_w_n_per_m(3 * r + c, k_cross(r, c));
      }
    }
    codec::ToMessage(cone_axis, m->mutable_friction_cone_axis_w());
    m->set_friction_cone_mu(cone_mu);
    m->set_ttl_s(ttl_s);
    m->set_contact_state(contact != nullptr ? ToMessage(contact->state) : v1::CONTACT_STATE_I);
  }
}

void ZeroForceModel(v1::ForceModel* model) {
  for (v1::FingerForceModel& m : *model->mutable_fingers()) {
    codec::ToMessage(Eigen::Vector3d::Zero(), m.mutable_f0_w_n());
    for (double& k : *m.mutable_stiffness_w_n_per_m()) k = 0.0;
    for (double& k : *m.mutable_cross_stiffness_w_n_per_m()) k = 0.0;
    m.set_friction_cone_mu(0.0);
  }
}

void FillTouchTrace(const contact::ContactOutput& contact, double sim_time_s, v1::TouchTrace* out) {
  out->set_sim_time_s(sim_time_s);
  while (out->fingers_size() < codec::kFingerSlots) out->add_fingers();
  for (int f = 0; f < codec::kFingerSlots; ++f) {
    const contact::FingerContactOutput& o = contact.finger[static_cast<std::size_t>(f)];
    v1::FingerTouch* t = out->mutable_fingers(f);
    t->set_finger(codec::FingerOfSlot(f));
    t->set_in_contact(o.touching);
    t->set_u_m(o.touch_uv_m.x());
    t->set_v_m(o.touch_uv_m.y());
    t->set_slip_u_m_per_s(o.slip_uv_m_per_s.x());
    t->set_slip_v_m_per_s(o.slip_uv_m_per_s.y());
    t->set_normal_force_n(o.normal_force_N);
    t->set_tangential_force_n(o.tangential_force_N);
    t->set_friction_normal_force_n(o.friction_normal_N);
    t->set_friction_tangential_force_n(o.friction_tangential_N);
    t->set_finger_angle_rad(o.finger_angle_rad);
    t->set_contact_state(ToMessage(contact.state));
  }
}

PatchCopy CopyPatch(const v1::LocalPatch& patch, std::uint32_t max_particle_id, dual_layer::PatchData* out) {
  const auto n = static_cast<std::size_t>(patch.particle_ids_size());
  if (n > out->ids.capacity()) return PatchCopy::kTooLarge;
  // arrays of other sizes than the ids' are malformed: refused before they could grow ours
  if (static_cast<std::size_t>(patch.rest_uv_m_size()) != 2 * n ||
      static_cast<std::size_t>(patch.position_w_m_size()) != 3 * n ||
      static_cast<std::size_t>(patch.velocity_w_m_per_s_size()) != 3 * n ||
      static_cast<std::size_t>(patch.is_border_size()) != n) {
    return PatchCopy::kMalformed;
  }
  out->Clear();
  out->patch_id = patch.patch_id();
  out->global_step = patch.global_step();
  out->global_time_s = patch.global_time_s();
  out->global_dt_s = patch.global_dt_s();
  out->link_round_trip_steps = patch.link_round_trip_steps();
  out->num_particles = static_cast<int>(n);
  out->ids.assign(patch.particle_ids().begin(), patch.particle_ids().end());
  out->rest_uv_m.assign(patch.rest_uv_m().begin(), patch.rest_uv_m().end());
  out->x_W_m.assign(patch.position_w_m().begin(), patch.position_w_m().end());
  out->v_W_m_per_s.assign(patch.velocity_w_m_per_s().begin(), patch.velocity_w_m_per_s().end());
  for (bool b : patch.is_border()) out->border.push_back(b ? 1 : 0);
  return dual_layer::IsBuildable(*out, max_particle_id) ? PatchCopy::kOk : PatchCopy::kMalformed;
}

void ToMessage(const dual_layer::PatchResultData& result, v1::PatchResult* out) {
  out->set_patch_id(result.patch_id);
  out->set_global_step(result.global_step);
  out->set_local_ticks(result.local_ticks);
  out->mutable_particle_ids()->Assign(result.ids.begin(), result.ids.end());
  out->mutable_position_w_m()->Assign(result.x_W_m.begin(), result.x_W_m.end());
  out->mutable_velocity_w_m_per_s()->Assign(result.v_W_m_per_s.begin(), result.v_W_m_per_s.end());
  out->mutable_external_force_w_n()->Assign(result.external_force_W_N.begin(), result.external_force_W_N.end());
}

}  // namespace haptex::local_contact
