#include "libs/device/passivity_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace haptex::device {

void PassivityConfig::Validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw std::invalid_argument(std::string("PassivityConfig: ") + name + " must be > 0, got " + std::to_string(v));
    }
  };
  positive(max_damping_N_s_per_m, "max_damping_N_s_per_m");
  positive(max_reserve_J, "max_reserve_J");
  positive(min_speed_m_per_s, "min_speed_m_per_s");
  if (!(deficit_tolerance_J >= 0.0) || !std::isfinite(deficit_tolerance_J)) {
    throw std::invalid_argument("PassivityConfig: deficit_tolerance_J must be >= 0, got " +
                                std::to_string(deficit_tolerance_J));
  }
}

PassivityController::PassivityController(const PassivityConfig& config) : config_(config) { config_.Validate(); }

Eigen::Vector3d PassivityController::Adjust(const Eigen::Vector3d& requested_W_N, const Eigen::Vector3d& v_W_m_per_s,
                                            double dt_s) {
  const double deficit_J = -energy_J_ - config_.deficit_tolerance_J;
  if (!config_.enabled || deficit_J <= 0.0 || !(dt_s > 0.0) || !v_W_m_per_s.allFinite()) return requested_W_N;
  const double speed2 = v_W_m_per_s.squaredNorm();
  if (speed2 < config_.min_speed_m_per_s * config_.min_speed_m_per_s) return requested_W_N;
  // damping that dissipates the whole deficit this step, within the controller's own limit
  const double damping = std::min(config_.max_damping_N_s_per_m, deficit_J / (speed2 * dt_s));
  ++counters_.damped_steps;
  counters_.dissipated_J += damping * speed2 * dt_s;
  return requested_W_N - damping * v_W_m_per_s;
}

void PassivityController::Observe(const Eigen::Vector3d& commanded_W_N, const Eigen::Vector3d& displacement_W_m) {
  if (!commanded_W_N.allFinite() || !displacement_W_m.allFinite()) return;
  energy_J_ = std::min(config_.max_reserve_J, energy_J_ - commanded_W_N.dot(displacement_W_m));
}

}  // namespace haptex::device
