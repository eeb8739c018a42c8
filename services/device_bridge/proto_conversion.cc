#include "services/device_bridge/proto_conversion.h"

#include <algorithm>

namespace haptex::device_bridge {
namespace {

void SetVec(const Eigen::Vector3d& v, v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

Eigen::Vector3d Vec(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

bool ToManipulator(v1::Finger finger, device::Manipulator* out) {
  switch (finger) {
    case v1::FINGER_THUMB: *out = device::Manipulator::kThumb; return true;
    case v1::FINGER_INDEX: *out = device::Manipulator::kIndex; return true;
    default: return false;
  }
}

v1::Finger ToFinger(device::Manipulator manipulator) {
  return manipulator == device::Manipulator::kThumb ? v1::FINGER_THUMB : v1::FINGER_INDEX;
}

device::ForceModel ToForceModel(const v1::FingerForceModel& in) {
  device::ForceModel model;
  model.force0_W_N = Vec(in.f0_w_n());
  model.x0_W_m = Vec(in.x0_w_m());
  if (in.stiffness_w_n_per_m_size() == 9) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) model.stiffness_W_N_per_m(r, c) = in.stiffness_w_n_per_m(3 * r + c);
    }
  }
  model.ttl_s = in.ttl_s();
  return model;
}

bool IsWellFormed(const v1::FingerForceModel& in) {
  return in.stiffness_w_n_per_m_size() == 9 || in.stiffness_w_n_per_m_size() == 0;
}

void FillFingerStates(const device::DeviceBridge& bridge, v1::FingerStates* out) {
  while (out->fingers_size() < 2) out->add_fingers();
  std::uint64_t newest = 0;
  for (int i = 0; i < 2; ++i) {
    const auto m = static_cast<device::Manipulator>(i);
    const device::FingerState& s = bridge.finger_state(m);
    v1::FingerState* f = out->mutable_fingers(i);
    f->set_finger(ToFinger(m));
    SetVec(s.p_W_m, f->mutable_position_w_m());
    f->mutable_orientation_wf()->set_w(s.q_WF.w());
    f->mutable_orientation_wf()->set_x(s.q_WF.x());
    f->mutable_orientation_wf()->set_y(s.q_WF.y());
    f->mutable_orientation_wf()->set_z(s.q_WF.z());
    SetVec(s.v_W_m_per_s, f->mutable_velocity_w_m_per_s());
    SetVec(s.p_pred_W_m, f->mutable_predicted_position_w_m());
    f->set_prediction_horizon_s(s.prediction_horizon_s);
    SetVec(s.force_measured_W_N, f->mutable_measured_force_w_n());
    newest = std::max<std::uint64_t>(newest, s.controller_sequence);
  }
  out->set_controller_sequence(newest);
  out->set_device_ok(!bridge.device_lost());
}

}  // namespace haptex::device_bridge
