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
  return {u2 * u * (10.0 - 15.0 * u + 6.0 * u2), 30.0 * u2 * (1.0 - 2.0 * u + u2) / duration_s};
}

std::size_t Slot(Manipulator m) { return static_cast<std::size_t>(m); }

// Signed offset of each finger from the fabric plane along the normal (thumb negative side).
constexpr std::array<double, kManipulatorCount> kSide = {-1.0, 1.0};

// Approach from rest to the fabric, then press: the common start of every grasp script.
// Returns the time at which the press is complete.
double Grasp(const ScriptParams& p, double t_s, std::array<bool, kManipulatorCount> moving, FingerTargets* out) {
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
  out->p_D_m = {a.thumb_D_m + u * (b.thumb_D_m - a.thumb_D_m), a.index_D_m + u * (b.index_D_m - a.index_D_m)};
  out->v_D_m_per_s = {(b.thumb_D_m - a.thumb_D_m) / span_s, (b.index_D_m - a.index_D_m) / span_s};
}

// Peak speed of a minimum-jerk move over distance d in time T is this times d / T.
constexpr double kMinimumJerkPeak = 1.875;

using Pose = std::array<Eigen::Vector3d, kManipulatorCount>;

// Walks kDemo's moves in order: visit(phase, from, to, move_s, hold_s) for each, until visit
// returns true (then so does this). A move takes both fingers from `from` to `to` along straight
// lines in move_s (one minimum-jerk blend, so each finger peaks at most at speed_m_per_s), then
// holds `to` for hold_s. No allocation.
template <class Visit>
bool VisitDemo(const ScriptParams& p, Visit&& visit) {
  constexpr std::size_t kT = 0;  // thumb: front of the fabric, pad facing +n
  constexpr std::size_t kI = 1;  // index: back of the fabric, pad facing -n
  // finger i's centre when its pad is `depth_m` past the fabric plane (< 0: a gap), shifted
  const auto place = [&p](std::size_t i, double depth_m, const Eigen::Vector3d& shift_D_m) {
    const Eigen::Vector3d inward = -kSide[i] * p.fabric_normal_D;
    return Eigen::Vector3d(p.fabric_point_D_m + (depth_m - p.pad_offset_m[i]) * inward + shift_D_m);
  };
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  const Eigen::Vector3d& stretch = p.stretch_D_m;
  Pose pose = {place(kT, -p.rest_gap_m, none), place(kI, -p.rest_gap_m, none)};
  const auto move = [&](DemoPhase phase, const Pose& to, double hold_s) {
    double distance_m = 0.0;
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      distance_m = std::max(distance_m, (to[i] - pose[i]).norm());
    }
    const Pose from = pose;
    pose = to;
    return visit(phase, from, to, kMinimumJerkPeak * distance_m / p.speed_m_per_s, hold_s);
  };

  // settle, then one finger (the thumb) touches the front
  if (move(DemoPhase::kSettle, pose, p.hold_s)) return true;
  Pose touch = pose;
  touch[kT] = place(kT, p.touch_depth_m, none);
  if (move(DemoPhase::kApproach, touch, 0.0)) return true;
  if (move(DemoPhase::kTouch, touch, p.hold_s)) return true;
  // the index comes to the back and both squeeze, then both pull along the fabric
  const Pose pinch = {place(kT, p.press_depth_m, none), place(kI, p.press_depth_m, none)};
  if (move(DemoPhase::kPinch, pinch, p.hold_s)) return true;
  const Pose stretched = {place(kT, p.press_depth_m, stretch), place(kI, p.press_depth_m, stretch)};
  if (move(DemoPhase::kStretch, stretched, p.hold_s)) return true;
  // rub: the thumb to +A, -A, +A, ... (rub_cycles times each way), then back to the middle
  const int strokes = 2 * p.rub_cycles + 1;
  for (int k = 0; k < strokes; ++k) {
    const bool last = k + 1 == strokes;
    const double along_m = last ? 0.0 : (k % 2 == 0 ? p.rub_amplitude_m : -p.rub_amplitude_m);
    Pose rub = stretched;
    rub[kT] += along_m * p.rub_direction_D;
    if (move(DemoPhase::kRub, rub, last ? p.hold_s : 0.0)) return true;
  }
  // open the pinch along the normal, then return to the rest pose
  const Pose released = {place(kT, -p.rest_gap_m, stretch), place(kI, -p.rest_gap_m, stretch)};
  if (move(DemoPhase::kRelease, released, p.hold_s)) return true;
  const Pose rest = {place(kT, -p.rest_gap_m, none), place(kI, -p.rest_gap_m, none)};
  return move(DemoPhase::kRetract, rest, 0.0);
}

// Where kDemo is at `t_s`: the phase, and the targets if `out` is not null.
DemoPhase EvaluateDemo(const ScriptParams& p, double t_s, FingerTargets* out) {
  double remaining_s = std::max(t_s, 0.0);
  DemoPhase phase = DemoPhase::kDone;
  Pose last{};
  const bool inside = VisitDemo(p, [&](DemoPhase ph, const Pose& from, const Pose& to, double move_s, double hold_s) {
    last = to;
    if (remaining_s < move_s) {
      phase = ph;
      if (out != nullptr) {
        const Blend b = MinimumJerk(remaining_s, move_s);
        for (std::size_t i = 0; i < kManipulatorCount; ++i) {
          out->p_D_m[i] = from[i] + b.s * (to[i] - from[i]);
          out->v_D_m_per_s[i] = b.ds_dt * (to[i] - from[i]);
        }
      }
      return true;
    }
    remaining_s -= move_s;
    if (remaining_s < hold_s) {
      phase = ph;
      if (out != nullptr) {
        out->p_D_m = to;
        out->v_D_m_per_s = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
      }
      return true;
    }
    remaining_s -= hold_s;
    return false;
  });
  if (!inside && out != nullptr) {
    out->p_D_m = last;
    out->v_D_m_per_s = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  }
  return phase;
}

}  // namespace

void ScriptParams::Validate() const {
  Require(fabric_point_D_m.allFinite(), "fabric_point_D_m must be finite");
  Require(fabric_normal_D.allFinite() && std::abs(fabric_normal_D.norm() - 1.0) < 1e-6,
          "fabric_normal_D must be a unit vector");
  Require(rest_gap_m >= 0.0 && rest_gap_m < 0.2, "rest_gap_m must be in [0, 0.2) m");
  Require(approach_duration_s > 0.0 && std::isfinite(approach_duration_s), "approach_duration_s must be > 0 s");
  Require(press_duration_s > 0.0 && std::isfinite(press_duration_s), "press_duration_s must be > 0 s");
  Require(press_depth_m >= 0.0 && press_depth_m < 0.05, "press_depth_m must be in [0, 0.05) m");
  Require(stretch_D_m.allFinite() && stretch_D_m.norm() < 0.2, "stretch_D_m must be finite, < 0.2 m");
  Require(stretch_duration_s > 0.0 && std::isfinite(stretch_duration_s), "stretch_duration_s must be > 0 s");
  Require(rub_direction_D.allFinite() && std::abs(rub_direction_D.norm() - 1.0) < 1e-6,
          "rub_direction_D must be a unit vector");
  Require(rub_amplitude_m >= 0.0 && rub_amplitude_m < 0.1, "rub_amplitude_m must be in [0, 0.1) m");
  Require(rub_frequency_Hz >= 0.0 && rub_frequency_Hz <= 20.0, "rub_frequency_Hz must be in [0, 20] Hz");
  Require(std::isfinite(lift_height_m) && std::abs(lift_height_m) < 0.2, "lift_height_m must be < 0.2 m");
  Require(up_D.allFinite() && std::abs(up_D.norm() - 1.0) < 1e-6, "up_D must be a unit vector");
  Require(lift_duration_s > 0.0 && std::isfinite(lift_duration_s), "lift_duration_s must be > 0 s");
  Require(speed_m_per_s > 0.0 && speed_m_per_s <= 1.0, "speed_m_per_s must be in (0, 1] m/s");
  Require(hold_s >= 0.0 && hold_s <= 60.0, "hold_s must be in [0, 60] s");
  Require(touch_depth_m >= 0.0 && touch_depth_m < 0.05, "touch_depth_m must be in [0, 0.05) m");
  Require(rub_cycles >= 1 && rub_cycles <= 50, "rub_cycles must be in [1, 50]");
  for (const double offset_m : pad_offset_m) {
    Require(offset_m >= 0.0 && offset_m < 0.05, "pad_offset_m must be in [0, 0.05) m");
  }
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
      const Eigen::Vector3d move_D_m = stretch ? p.stretch_D_m : Eigen::Vector3d(p.lift_height_m * p.up_D);
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
    case ScriptKind::kDemo:
      EvaluateDemo(p, t_s, &out);
      break;
  }
  return out;
}

DemoPhase DemoPhaseAt(const ScriptParams& params, double t_s) { return EvaluateDemo(params, t_s, nullptr); }

double DemoDuration(const ScriptParams& params) {
  double total_s = 0.0;
  VisitDemo(params, [&total_s](DemoPhase, const Pose&, const Pose&, double move_s, double hold_s) {
    total_s += move_s + hold_s;
    return false;
  });
  return total_s;
}

const char* DemoPhaseName(DemoPhase phase) {
  switch (phase) {
    case DemoPhase::kSettle:
      return "settle";
    case DemoPhase::kApproach:
      return "approach";
    case DemoPhase::kTouch:
      return "touch";
    case DemoPhase::kPinch:
      return "pinch";
    case DemoPhase::kStretch:
      return "stretch";
    case DemoPhase::kRub:
      return "rub";
    case DemoPhase::kRelease:
      return "release";
    case DemoPhase::kRetract:
      return "retract";
    case DemoPhase::kDone:
      return "done";
  }
  return "unknown";
}

ScriptKind ScriptKindFromName(const std::string& name) {
  if (name == "idle") return ScriptKind::kIdle;
  if (name == "approach") return ScriptKind::kApproachAndTouch;
  if (name == "grasp") return ScriptKind::kGraspAndSqueeze;
  if (name == "pinch") return ScriptKind::kPinchAndStretch;
  if (name == "rub") return ScriptKind::kRub;
  if (name == "lift") return ScriptKind::kLift;
  if (name == "playback") return ScriptKind::kPlayback;
  if (name == "demo") return ScriptKind::kDemo;
  throw std::invalid_argument("unknown script '" + name +
                              "' (idle, approach, grasp, pinch, rub, lift, playback or demo)");
}

}  // namespace haptex::device
