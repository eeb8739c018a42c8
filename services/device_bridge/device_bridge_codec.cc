#include "services/device_bridge/device_bridge_codec.h"

#include <algorithm>

#include "libs/codec/message_conversion.h"

namespace haptex::device_bridge {

bool ToManipulator(v1::Finger finger, device::Manipulator* out) {
  const int slot = codec::FingerSlot(finger);
  if (slot < 0) return false;
  *out = slot == codec::kThumbSlot ? device::Manipulator::kThumb : device::Manipulator::kIndex;
  return true;
}

v1::Finger ToFinger(device::Manipulator manipulator) {
  return codec::FingerOfSlot(manipulator == device::Manipulator::kThumb ? codec::kThumbSlot : codec::kIndexSlot);
}

namespace {

// A 3 x 3 matrix sent row by row; an empty field is zero (IsWellFormed refuses other sizes).
Eigen::Matrix3d Matrix3FromRowMajor(const google::protobuf::RepeatedField<double>& values) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  if (values.size() != 9) return m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = values.Get(3 * r + c);
  }
  return m;
}

}  // namespace

device::ForceModel ToForceModel(const v1::FingerForceModel& in) {
  device::ForceModel model;
  model.force0_W_N = codec::ToEigen(in.f0_w_n());
  model.x0_W_m = codec::ToEigen(in.x0_w_m());
  model.stiffness_W_N_per_m = Matrix3FromRowMajor(in.stiffness_w_n_per_m());
  model.cross_stiffness_W_N_per_m = Matrix3FromRowMajor(in.cross_stiffness_w_n_per_m());
  model.friction_cone_axis_W = codec::ToEigen(in.friction_cone_axis_w());
  model.friction_cone_mu = in.friction_cone_mu();
  model.ttl_s = in.ttl_s();
  return model;
}

device::ForceModel ToForceModel(const v1::FingerForceModel& in, const v1::FingerForceModel* other) {
  device::ForceModel model = ToForceModel(in);
  if (other != nullptr) {
    model.other_x0_W_m = codec::ToEigen(other->x0_w_m());
  } else {
    model.cross_stiffness_W_N_per_m.setZero();  // no anchor for the other finger: no cross term
  }
  return model;
}

bool IsWellFormed(const v1::FingerForceModel& in) {
  const auto matrix = [](int values) { return values == 9 || values == 0; };
  return matrix(in.stiffness_w_n_per_m_size()) && matrix(in.cross_stiffness_w_n_per_m_size());
}

void FillFingerStates(const device::DeviceBridge& bridge, v1::FingerStates* out) {
  while (out->fingers_size() < 2) out->add_fingers();
  std::uint64_t newest = 0;
  for (int i = 0; i < 2; ++i) {
    const auto m = static_cast<device::Manipulator>(i);
    const device::FingerState& s = bridge.model_finger_state(m);
    v1::FingerState* f = out->mutable_fingers(i);
    f->set_finger(ToFinger(m));
    codec::ToMessage(s.p_W_m, f->mutable_position_w_m());
    codec::ToMessage(s.q_WF, f->mutable_orientation_wf());
    codec::ToMessage(s.v_W_m_per_s, f->mutable_velocity_w_m_per_s());
    // the contact models answer a link round trip later: they get the pose for then
    codec::ToMessage(s.p_link_pred_W_m, f->mutable_predicted_position_w_m());
    f->set_prediction_horizon_s(s.prediction_horizon_s + s.link_horizon_s);
    f->set_link_horizon_s(s.link_horizon_s);
    codec::ToMessage(s.force_measured_W_N, f->mutable_measured_force_w_n());
    newest = std::max<std::uint64_t>(newest, s.controller_sequence);
  }
  out->set_controller_sequence(newest);
  out->set_device_ok(!bridge.device_lost());
}

}  // namespace haptex::device_bridge
