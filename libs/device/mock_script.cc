#include "libs/device/mock_script.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

void Require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument("ScriptParams: " + message);
}

// Minimum-jerk blend: position fraction and its time derivative for a move of `duration_s`.
struct Blend {
  double s = 0.0;
  double ds_dt = 0.0;
};

Blend MinimumJerk(double t_s, double duration_s) {
  if (t_s <= 0.0) return {0.0, 0.0};
  if (t_s >= duration_s) return {1.0, 0.0};
  const double u = t_s / duration_s;
  const double u2 = u * u;
  return {u2 * u * (10.0 - 15.0 * u + 6.0 * u2),
          30.0 * u2 * (1.0 - 2.0 * u + u2) / duration_s};
}

std::size_t Slot(Manipulator m) { return static_cast<std::size_t>(m); }

// Signed offset of each finger from the fabric plane along the normal (thumb negative side).
constexpr std::array<double, kManipulatorCount> kSide = {-1.0, 1.0};

// Approach from rest to the fabric, then press: the common start of every grasp script.
// Returns the time at which the press is complete.
double Grasp(const ScriptParams& p, double t_s, std::array<bool, kManipulatorCount> moving,
             FingerTargets* out) {
  const Blend approach = MinimumJerk(t_s, p.approach_duration_s);
  const Blend press = MinimumJerk(t_s - p.approach_duration_s, p.press_duration_s);
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    const Eigen::Vector3d n = kSide[i] * p.fabric_normal_D;
    if (!moving[i]) {
      out->p_D_m[i] = p.fabric_point_D_m + p.rest_gap_m * n;
      out->v_D_m_per_s[i].setZero();
      continue;
    }
    // offset along n: rest_gap -> 0 (approach) -> -press_depth (press through the plane)
    const double offset = p.rest_gap_m * (1.0 - approach.s) - p.press_depth_m * press.s;
    const double d_offset = -p.rest_gap_m * approach.ds_dt - p.press_depth_m * press.ds_dt;
    out->p_D_m[i] = p.fabric_point_D_m + offset * n;
    out->v_D_m_per_s[i] = d_offset * n;
  }
  return p.approach_duration_s + p.press_duration_s;
}

void Playback(const std::vector<TrajectorySample>& samples, double t_s, FingerTargets* out) {
  // hold the ends; linear interpolation in between (velocity = segment slope)
  const auto after = std::upper_bound(samples.begin(), samples.end(), t_s,
                                      [](double t, const TrajectorySample& s) { return t < s.t_s; });
  if (after == samples.begin() || after == samples.end()) {
    const TrajectorySample& s = after == samples.begin() ? samples.front() : samples.back();
    out->p_D_m = {s.thumb_D_m, s.index_D_m};
    out->v_D_m_per_s = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
    return;
  }
  const TrajectorySample& b = *after;
  const TrajectorySample& a = *(after - 1);
  const double span_s = b.t_s - a.t_s;
  const double u = (t_s - a.t_s) / span_s;
  out->p_D_m = {a.thumb_D_m + u * (b.thumb_D_m - a.thumb_D_m),
                a.index_D_m + u * (b.index_D_m - a.index_D_m)};
  out->v_D_m_per_s = {(b.thumb_D_m - a.thumb_D_m) / span_s, (b.index_D_m - a.index_D_m) / span_s};
}

}  // namespace

void ScriptParams::Validate() const {
  Require(fabric_point_D_m.allFinite(), "fabric_point_D_m must be finite");
  Require(fabric_normal_D.allFinite() && std::abs(fabric_normal_D.norm() - 1.0) < 1e-6,
          "fabric_normal_D must be a unit vector");
  Require(rest_gap_m >= 0.0 && rest_gap_m < 0.2, "rest_gap_m must be in [0, 0.2) m");
  Require(approach_duration_s > 0.0 && std::isfinite(approach_duration_s),
          "approach_duration_s must be > 0 s");
  Require(press_duration_s > 0.0 && std::isfinite(press_duration_s), "press_duration_s must be > 0 s");
  Require(press_depth_m >= 0.0 && press_depth_m < 0.05, "press_depth_m must be in [0, 0.05) m");
  Require(stretch_D_m.allFinite() && stretch_D_m.norm() < 0.2, "stretch_D_m must be finite, < 0.2 m");
  Require(stretch_duration_s > 0.0 && std::isfinite(stretch_duration_s),
          "stretch_duration_s must be > 0 s");
  Require(rub_direction_D.allFinite() && std::abs(rub_direction_D.norm() - 1.0) < 1e-6,
          "rub_direction_D must be a unit vector");
  Require(rub_amplitude_m >= 0.0 && rub_amplitude_m < 0.1, "rub_amplitude_m must be in [0, 0.1) m");
  Require(rub_frequency_Hz >= 0.0 && rub_frequency_Hz <= 20.0, "rub_frequency_Hz must be in [0, 20] Hz");
  Require(std::isfinite(lift_height_m) && std::abs(lift_height_m) < 0.2, "lift_height_m must be < 0.2 m");
  Require(lift_duration_s > 0.0 && std::isfinite(lift_duration_s), "lift_duration_s must be > 0 s");
  if (kind == ScriptKind::kPlayback) {
    Require(trajectory.size() >= 2, "kPlayback needs a trajectory of at least 2 samples");
    for (std::size_t i = 0; i < trajectory.size(); ++i) {
      const TrajectorySample& s = trajectory[i];
      Require(std::isfinite(s.t_s) && s.thumb_D_m.allFinite() && s.index_D_m.allFinite(),
              "trajectory sample " + std::to_string(i) + " is not finite");
      Require(i == 0 || s.t_s > trajectory[i - 1].t_s,
              "trajectory t_s must increase strictly (sample " + std::to_string(i) + ")");
    }
  }
}

FingerTargets EvaluateScript(const ScriptParams& p, double t_s) {
  t_s = std::max(t_s, 0.0);
  FingerTargets out;
  switch (p.kind) {
    case ScriptKind::kIdle:
      Grasp(p, 0.0, {false, false}, &out);
      break;
    case ScriptKind::kApproachAndTouch: {
      std::array<bool, kManipulatorCount> moving{false, false};
      moving[Slot(p.touch_finger)] = true;
      Grasp(p, t_s, moving, &out);
      break;
    }
    case ScriptKind::kGraspAndSqueeze:
      Grasp(p, t_s, {true, true}, &out);
      break;
    case ScriptKind::kPinchAndStretch:
    case ScriptKind::kLift: {
      const double t0 = Grasp(p, t_s, {true, true}, &out);
      const bool stretch = p.kind == ScriptKind::kPinchAndStretch;
      const Eigen::Vector3d move_D_m =
          stretch ? p.stretch_D_m : Eigen::Vector3d(0.0, 0.0, p.lift_height_m);
      const Blend b = MinimumJerk(t_s - t0, stretch ? p.stretch_duration_s : p.lift_duration_s);
      for (std::size_t i = 0; i < kManipulatorCount; ++i) {
        out.p_D_m[i] += b.s * move_D_m;
        out.v_D_m_per_s[i] += b.ds_dt * move_D_m;
      }
      break;
    }
    case ScriptKind::kRub: {
      const double t0 = Grasp(p, t_s, {true, true}, &out);
      if (t_s <= t0) break;
      const double tau_s = t_s - t0;
      const double w = 2.0 * std::numbers::pi * p.rub_frequency_Hz;
      const std::size_t thumb = Slot(Manipulator::kThumb);
      out.p_D_m[thumb] += p.rub_amplitude_m * std::sin(w * tau_s) * p.rub_direction_D;
      out.v_D_m_per_s[thumb] += p.rub_amplitude_m * w * std::cos(w * tau_s) * p.rub_direction_D;
      break;
    }
    case ScriptKind::kPlayback:
      Playback(p.trajectory, t_s, &out);
      break;
  }
  return out;
}

}  // namespace haptex::device
