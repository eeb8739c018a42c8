#include "libs/device/finger_state_estimator.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

// Rotation vector (axis * angle, shortest way) of a unit quaternion.
Eigen::Vector3d RotationVector(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < 1e-12) return 2.0 * q.vec();
  return (2.0 * std::atan2(s, q.w()) / s) * q.vec();
}

Eigen::Quaterniond FromRotationVector(const Eigen::Vector3d& r) {
  const double angle = r.norm();
  if (angle < 1e-12) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, r / angle));
}

}  // namespace

void FingerStateEstimatorConfig::Validate() const {
  if (!(velocity_cutoff_Hz > 0.0) || !std::isfinite(velocity_cutoff_Hz)) {
    throw std::invalid_argument("FingerStateEstimatorConfig: velocity_cutoff_Hz must be > 0, got " +
                                std::to_string(velocity_cutoff_Hz));
  }
  if (!(prediction_horizon_s >= 0.0) || !(prediction_horizon_s <= 0.1)) {
    throw std::invalid_argument("FingerStateEstimatorConfig: prediction_horizon_s must be in [0, 0.1] s, got " +
                                std::to_string(prediction_horizon_s));
  }
  if (!(max_sample_gap_s > 0.0) || !std::isfinite(max_sample_gap_s)) {
    throw std::invalid_argument("FingerStateEstimatorConfig: max_sample_gap_s must be > 0, got " +
                                std::to_string(max_sample_gap_s));
  }
}

FingerStateEstimator::FingerStateEstimator(const FingerStateEstimatorConfig& config) : config_(config), tau_s_(0.0) {
  config_.Validate();
  tau_s_ = 1.0 / (2.0 * std::numbers::pi * config_.velocity_cutoff_Hz);
}

void FingerStateEstimator::Reset() {
  has_previous_ = false;
  v_W_m_per_s_.setZero();
  w_W_rad_per_s_.setZero();
}

void FingerStateEstimator::Update(const Eigen::Vector3d& p_W_m, const Eigen::Quaterniond& q_WF,
                                  std::uint64_t controller_time_ns, FingerState* state) {
  const Eigen::Quaterniond q = q_WF.normalized();
  if (has_previous_ && controller_time_ns > previous_time_ns_) {
    const double dt_s = static_cast<double>(controller_time_ns - previous_time_ns_) * 1e-9;
    if (dt_s > config_.max_sample_gap_s) {
      // too old to difference against: restart from rest
      v_W_m_per_s_.setZero();
      w_W_rad_per_s_.setZero();
    } else {
      // low-pass of the finite difference, exact discretisation of a first-order lag
      const double alpha = 1.0 - std::exp(-dt_s / tau_s_);
      const Eigen::Vector3d v_raw = (p_W_m - previous_p_W_m_) / dt_s;
      const Eigen::Vector3d w_raw = RotationVector(q * previous_q_WF_.conjugate()) / dt_s;
      v_W_m_per_s_ += alpha * (v_raw - v_W_m_per_s_);
      w_W_rad_per_s_ += alpha * (w_raw - w_W_rad_per_s_);
    }
  }
  if (!has_previous_ || controller_time_ns >= previous_time_ns_) {
    has_previous_ = true;
    previous_time_ns_ = controller_time_ns;
    previous_p_W_m_ = p_W_m;
    previous_q_WF_ = q;
  }

  const double h = config_.prediction_horizon_s;
  state->valid = true;
  state->controller_time_ns = controller_time_ns;
  state->p_W_m = p_W_m;
  state->q_WF = q;
  state->v_W_m_per_s = v_W_m_per_s_;
  state->w_W_rad_per_s = w_W_rad_per_s_;
  state->prediction_horizon_s = h;
  state->p_pred_W_m = p_W_m + h * v_W_m_per_s_;
  state->q_pred_WF = (FromRotationVector(h * w_W_rad_per_s_) * q).normalized();
  const double h_link = h + link_horizon_s_;
  state->link_horizon_s = link_horizon_s_;
  state->p_link_pred_W_m = p_W_m + h_link * v_W_m_per_s_;
  state->q_link_pred_WF = (FromRotationVector(h_link * w_W_rad_per_s_) * q).normalized();
}

void FingerStateEstimator::SetLinkHorizon(double horizon_s) {
  if (!std::isfinite(horizon_s)) return;
  link_horizon_s_ = std::clamp(horizon_s, 0.0, kMaxLinkHorizon_s);
}

void FingerStateEstimator::SetPredictionHorizon(double horizon_s) {
  if (!std::isfinite(horizon_s)) return;
  config_.prediction_horizon_s = std::clamp(horizon_s, 0.0, 0.1);
}

}  // namespace haptex::device
