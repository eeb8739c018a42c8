#pragma once
// Velocity estimation from quantised positions and pose prediction one link latency ahead.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "libs/device/finger_state.h"

namespace haptex::device {

/// Filter and prediction settings. Validate() throws std::invalid_argument with a clear message.
struct FingerStateEstimatorConfig {
  /// Cut-off of the first-order low-pass applied to finite-difference velocities. Lower: less
  /// quantisation noise (0.032 mm / 0.2 ms = 0.16 m/s per step), more lag.
  double velocity_cutoff_Hz = 60.0;
  /// How far ahead the pose is predicted: one link latency (controller -> host -> controller).
  double prediction_horizon_s = 0.001;
  /// Samples further apart than this restart the velocity estimate (lost packets, reconnect).
  double max_sample_gap_s = 0.020;

  void Validate() const;
};

/// Estimates velocity (first-order low-pass on finite differences, time steps taken from the
/// controller clock so network jitter does not enter) and extrapolates the pose linearly.
class FingerStateEstimator {
 public:
  /// @throws std::invalid_argument if `config` is invalid.
  explicit FingerStateEstimator(const FingerStateEstimatorConfig& config);

  /// Folds one measured pose into `*state` (pose, velocities, prediction). `controller_time_ns`
  /// must not go backwards; an equal time only refreshes the pose.
  void Update(const Eigen::Vector3d& p_W_m, const Eigen::Quaterniond& q_WF, std::uint64_t controller_time_ns,
              FingerState* state);

  /// Forgets history: the next Update starts from zero velocity.
  void Reset();

  const FingerStateEstimatorConfig& config() const { return config_; }
  /// Changes the prediction horizon at run time (e.g. to the measured latency); clamped to
  /// [0, 0.1] s, non-finite values ignored. Takes effect at the next Update.
  void SetPredictionHorizon(double horizon_s);
  /// The haptic link's round trip, predicted beyond the prediction horizon for the pose sent to
  /// the contact models; clamped to [0, kMaxLinkHorizon_s], non-finite values ignored.
  void SetLinkHorizon(double horizon_s);
  static constexpr double kMaxLinkHorizon_s = 0.5;

 private:
  FingerStateEstimatorConfig config_;
  double link_horizon_s_ = 0.0;
  double tau_s_;
  bool has_previous_ = false;
  std::uint64_t previous_time_ns_ = 0;
  Eigen::Vector3d previous_p_W_m_{Eigen::Vector3d::Zero()};
  Eigen::Quaterniond previous_q_WF_{Eigen::Quaterniond::Identity()};
  Eigen::Vector3d v_W_m_per_s_{Eigen::Vector3d::Zero()};
  Eigen::Vector3d w_W_rad_per_s_{Eigen::Vector3d::Zero()};
};

}  // namespace haptex::device
