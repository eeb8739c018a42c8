#pragma once
// What the bridge knows about one fingertip: the latest measured pose, filtered velocities and
// the pose predicted one link latency ahead. World frame W (proto/haptex/v1/common.proto).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace haptex::device {

/// One fingertip's estimated state. F is the contact-part (fingertip pad) frame.
struct FingerState {
  bool valid = false;                              ///< false until a calibrated pose has been received
  std::uint32_t controller_sequence = 0;           ///< StatusFrame.sequence this state contains
  std::uint64_t controller_time_ns = 0;            ///< controller clock of that frame
  double received_s = 0.0;                         ///< host clock when that frame arrived
  Eigen::Vector3d p_W_m{Eigen::Vector3d::Zero()};  ///< measured (quantised) position
  Eigen::Quaterniond q_WF{Eigen::Quaterniond::Identity()};
  Eigen::Vector3d v_W_m_per_s{Eigen::Vector3d::Zero()};    ///< filtered linear velocity
  Eigen::Vector3d w_W_rad_per_s{Eigen::Vector3d::Zero()};  ///< filtered angular velocity
  double prediction_horizon_s = 0.0;
  Eigen::Vector3d p_pred_W_m{Eigen::Vector3d::Zero()};  ///< position at +prediction_horizon_s
  Eigen::Quaterniond q_pred_WF{Eigen::Quaterniond::Identity()};
  /// The pose a haptic link round trip further ahead (+prediction_horizon_s + link_horizon_s):
  /// where the finger will be when a force model computed from this state comes back.
  double link_horizon_s = 0.0;
  Eigen::Vector3d p_link_pred_W_m{Eigen::Vector3d::Zero()};
  Eigen::Quaterniond q_link_pred_WF{Eigen::Quaterniond::Identity()};
  Eigen::Vector3d force_measured_W_N{Eigen::Vector3d::Zero()};  ///< device force sensor
  std::uint16_t device_flags = 0;                               ///< manipulator_flags from the controller
};

}  // namespace haptex::device
