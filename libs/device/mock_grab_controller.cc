#include "libs/device/mock_grab_controller.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace haptex::device {
namespace {

void Require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument("MockControllerConfig: " + message);
}

bool PositiveFinite(double v) { return v > 0.0 && std::isfinite(v); }

}  // namespace

void MockControllerConfig::Validate() const {
  Require(PositiveFinite(finger.mass_kg), "finger.mass_kg must be > 0");
  Require(finger.user_stiffness_N_per_m >= 0.0 && std::isfinite(finger.user_stiffness_N_per_m),
          "finger.user_stiffness_N_per_m must be >= 0");
  Require(finger.user_damping_N_s_per_m >= 0.0 && std::isfinite(finger.user_damping_N_s_per_m),
          "finger.user_damping_N_s_per_m must be >= 0");
  Require(finger.device_damping_N_s_per_m >= 0.0 && std::isfinite(finger.device_damping_N_s_per_m),
          "finger.device_damping_N_s_per_m must be >= 0");
  Require(finger.force_time_constant_s >= 0.0 && std::isfinite(finger.force_time_constant_s),
          "finger.force_time_constant_s must be >= 0");
  Require(position_quantum_m >= 0.0 && position_quantum_m < 0.001, "position_quantum_m must be in [0, 1 mm)");
  Require(force_noise_N >= 0.0 && force_noise_N < 5.0, "force_noise_N must be in [0, 5) N");
  Require(PositiveFinite(host_timeout_s), "host_timeout_s must be > 0");
  Require(PositiveFinite(max_world_step_s), "max_world_step_s must be > 0");
  Require(first_status_sequence != 0, "first_status_sequence must not be 0 (0 means \"none\" in echoes)");
  Require(PositiveFinite(slew_N_per_s), "slew_N_per_s must be > 0");
  Require(PositiveFinite(peak_force_N), "peak_force_N must be > 0");
  Require((limits.workspace_half_extent_m.array() > 0.0f).all(), "limits.workspace_half_extent_m must be > 0");
}

MockGrabController::MockGrabController(const MockControllerConfig& config, ScriptParams script)
    : config_(config), script_(std::move(script)), rng_(config.seed) {
  config_.Validate();
  script_.Validate();
  const FingerTargets start = EvaluateScript(script_, 0.0);
  // pads face each other through the fabric: F's z axis is the pad normal
  const Eigen::Vector3d n = script_.fabric_normal_D;
  q_DF_[0] = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), n);
  q_DF_[1] = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), -n);
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    fingers_[i].p_D_m = start.p_D_m[i];
    fingers_[i].flags = manipulator_flags::kCalibrated;
  }
}

void MockGrabController::SetFinger(Manipulator m, const Eigen::Vector3d& p_D_m, const Eigen::Vector3d& v_D_m_per_s) {
  MockFingerState& f = fingers_[static_cast<std::size_t>(m)];
  f.p_D_m = p_D_m;
  f.v_D_m_per_s = v_D_m_per_s;
}

FrameError MockGrabController::OnCommandDatagram(std::span<const std::byte> datagram, double t_s) {
  CommandFrame frame;
  const FrameError error = DecodeCommandFrame(datagram, config_.limits, &frame);
  frame_counters_.Add(error);
  if (error != FrameError::kNone) {
    command_rejected_ = true;
    return error;
  }
  // sequence 0 is never sent; after a timeout any other sequence is accepted (host restart)
  if (frame.sequence == 0 || (has_command_ && !host_timed_out_ && !SequenceNewer(frame.sequence, command_.sequence))) {
    ++counters_.commands_out_of_order;
    return error;
  }
  command_ = frame;
  has_command_ = true;
  last_command_run_s_ = t_s - paused_s_;
  return error;
}

void MockGrabController::Step(double t_s, double dt_s, std::span<std::byte, kStatusFrameSize> out) {
  ++counters_.steps;
  const double t_end_s = t_s + dt_s;
  // controller watchdog: silence or a shutdown request means zero force
  // "silent for 5 ms" includes exactly 5 ms despite rounding in t_s
  const bool timed_out = !has_command_ || (t_s - paused_s_) - last_command_run_s_ >= config_.host_timeout_s - 1e-7;
  if (timed_out && !host_timed_out_ && !(command_.host_flags & host_flags::kShutdown)) {
    ++counters_.host_timeouts;
  }
  host_timed_out_ = timed_out;
  const bool shutdown = has_command_ && (command_.host_flags & host_flags::kShutdown);

  if (dt_s > config_.max_world_step_s) {
    ++counters_.world_pauses;
    paused_s_ += dt_s - config_.max_world_step_s;
    dt_s = config_.max_world_step_s;
  }

  const FingerTargets target = EvaluateScript(script_, t_end_s);
  const MockFingerParams& fp = config_.finger;
  const double force_alpha = fp.force_time_constant_s > 0.0 ? 1.0 - std::exp(-dt_s / fp.force_time_constant_s) : 1.0;
  const Eigen::Array3d bound = config_.limits.workspace_half_extent_m.cast<double>().array();

  StatusFrame status;
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    MockFingerState& f = fingers_[i];
    const ManipulatorCommand& cmd = command_.manipulators[i];
    std::uint16_t flags = manipulator_flags::kCalibrated;

    // the command the motors track, clamped to the controller's own peak
    Eigen::Vector3d commanded = Eigen::Vector3d::Zero();
    if (!timed_out && !shutdown && (cmd.flags & command_flags::kForceEnable)) {
      commanded = cmd.force_D_N.cast<double>();
      flags |= manipulator_flags::kForceEnabled;
      const double norm = commanded.norm();
      if (norm > config_.peak_force_N) {
        commanded *= config_.peak_force_N / norm;
        flags |= manipulator_flags::kForceSaturated;
      }
    }
    if (!commanded.isZero(0.0)) {
      Eigen::Vector3d step = commanded - f.commanded_force_D_N;
      const double max_step_N = config_.slew_N_per_s * dt_s;
      if (step.norm() > max_step_N) {
        step *= max_step_N / step.norm();
        flags |= manipulator_flags::kForceSaturated;
      }
      commanded = f.commanded_force_D_N + step;
    }
    f.commanded_force_D_N = commanded;
    f.applied_force_D_N += force_alpha * (commanded - f.applied_force_D_N);

    // finger dynamics, semi-implicit Euler: user pull + rendered force - mechanism friction
    const Eigen::Vector3d user_N = fp.user_stiffness_N_per_m * (target.p_D_m[i] - f.p_D_m) +
                                   fp.user_damping_N_s_per_m * (target.v_D_m_per_s[i] - f.v_D_m_per_s);
    const Eigen::Vector3d a = (user_N + f.applied_force_D_N - fp.device_damping_N_s_per_m * f.v_D_m_per_s) / fp.mass_kg;
    f.v_D_m_per_s += dt_s * a;
    f.p_D_m += dt_s * f.v_D_m_per_s;

    // mechanical stops at the workspace faces
    for (int k = 0; k < 3; ++k) {
      if (std::abs(f.p_D_m[k]) >= bound[k]) {
        f.p_D_m[k] = std::copysign(bound[k], f.p_D_m[k]);
        if (f.v_D_m_per_s[k] * f.p_D_m[k] > 0.0) f.v_D_m_per_s[k] = 0.0;
        flags |= manipulator_flags::kWorkspaceLimit;
      }
    }
    f.flags = flags;

    // what the sensors report: quantised encoders, noisy force sensor
    ManipulatorStatus& m = status.manipulators[i];
    Eigen::Vector3d p_reported = f.p_D_m;
    if (config_.position_quantum_m > 0.0) {
      p_reported = (f.p_D_m / config_.position_quantum_m).array().round() * config_.position_quantum_m;
    }
    m.p_D_m = p_reported.cast<float>();
    m.q_DF = q_DF_[i].cast<float>();
    const Eigen::Vector3d noise(rng_.Uniform(), rng_.Uniform(), rng_.Uniform());
    m.force_D_N = (f.applied_force_D_N + config_.force_noise_N * noise).cast<float>();
    m.flags = flags;
  }

  status.controller_flags = static_cast<std::uint16_t>((timed_out && !shutdown ? controller_flags::kHostTimeout : 0) |
                                                       (command_rejected_ ? controller_flags::kCommandRejected : 0));
  command_rejected_ = false;
  sequence_ = counters_.steps == 1 ? config_.first_status_sequence : NextSequence(sequence_);
  status.sequence = sequence_;
  status.echo_host_sequence = has_command_ ? command_.sequence : 0;
  status.controller_time_ns = static_cast<std::uint64_t>(std::llround(std::max(t_end_s, 0.0) * 1e9));
  EncodeStatusFrame(status, out);
}

}  // namespace haptex::device
