#include "libs/device/mock_script.h"

#include <Eigen/Geometry>
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

// One move of a phased script (kDemo, kFold): both fingers from `from` to `to` in move_s (one
// minimum-jerk blend), then `to` held for hold_s. A straight move when angle_rad is 0; otherwise
// both fingers turn by angle_rad about the line through pivot_D_m along axis_D (unit) while that
// line moves by lift_D_m, which takes `from` to `to`: a pinch turned this way keeps its fingers'
// distance throughout.
struct Move {
  std::uint8_t phase = 0;
  Pose from{}, to{};
  double move_s = 0.0, hold_s = 0.0;
  Eigen::Vector3d pivot_D_m{Eigen::Vector3d::Zero()}, axis_D{Eigen::Vector3d::UnitX()};
  double angle_rad = 0.0;
  Eigen::Vector3d lift_D_m{Eigen::Vector3d::Zero()};
};

// Where a move is `s` of the way (ds_dt its rate), into `out`.
void Interpolate(const Move& m, const Blend& b, FingerTargets* out) {
  for (std::size_t i = 0; i < kManipulatorCount; ++i) {
    if (m.angle_rad == 0.0) {
      out->p_D_m[i] = m.from[i] + b.s * (m.to[i] - m.from[i]);
      out->v_D_m_per_s[i] = b.ds_dt * (m.to[i] - m.from[i]);
      continue;
    }
    const Eigen::Vector3d arm = Eigen::AngleAxisd(b.s * m.angle_rad, m.axis_D) * (m.from[i] - m.pivot_D_m);
    out->p_D_m[i] = m.pivot_D_m + b.s * m.lift_D_m + arm;
    out->v_D_m_per_s[i] = b.ds_dt * (m.lift_D_m + m.angle_rad * m.axis_D.cross(arm));
  }
}

// Builds the moves of a phased script in order: each finger's path peaks at speed_m_per_s.
// visit(move) is called for each until it returns true (then so does the walk). No allocation.
class MoveWalk {
 public:
  explicit MoveWalk(const ScriptParams& p) : p_(p) {}

  // finger i's centre when its pad is `depth_m` past the fabric plane (< 0: a gap), shifted
  Eigen::Vector3d Place(std::size_t i, double depth_m, const Eigen::Vector3d& shift_D_m) const {
    const Eigen::Vector3d inward = -kSide[i] * p_.fabric_normal_D;
    return p_.fabric_point_D_m + (depth_m - p_.pad_offset_m[i]) * inward + shift_D_m;
  }
  const Pose& pose() const { return pose_; }
  void Start(const Pose& pose) { pose_ = pose; }

  template <class Visit>
  bool Straight(std::uint8_t phase, const Pose& to, double hold_s, Visit&& visit) {
    double distance_m = 0.0;
    for (std::size_t i = 0; i < kManipulatorCount; ++i) distance_m = std::max(distance_m, (to[i] - pose_[i]).norm());
    Move m;
    m.phase = phase;
    m.from = pose_;
    m.to = to;
    m.move_s = kMinimumJerkPeak * distance_m / p_.speed_m_per_s;
    m.hold_s = hold_s;
    pose_ = to;
    return visit(m);
  }

  template <class Visit>
  bool Turn(std::uint8_t phase, const Eigen::Vector3d& pivot_D_m, const Eigen::Vector3d& axis_D, double angle_rad,
            const Eigen::Vector3d& lift_D_m, double hold_s, Visit&& visit) {
    Move m;
    m.phase = phase;
    m.from = pose_;
    m.pivot_D_m = pivot_D_m;
    m.axis_D = axis_D;
    m.angle_rad = angle_rad;
    m.lift_D_m = lift_D_m;
    // a finger's speed is at most the lift's plus the turn's, each scaled by the blend's rate
    double path_m = 0.0;
    for (std::size_t i = 0; i < kManipulatorCount; ++i) {
      const Eigen::Vector3d arm = pose_[i] - pivot_D_m;
      path_m = std::max(path_m, lift_D_m.norm() + (arm - arm.dot(axis_D) * axis_D).norm() * std::abs(angle_rad));
      m.to[i] = pivot_D_m + lift_D_m + Eigen::AngleAxisd(angle_rad, axis_D) * arm;
    }
    m.move_s = kMinimumJerkPeak * path_m / p_.speed_m_per_s;
    m.hold_s = hold_s;
    pose_ = m.to;
    return visit(m);
  }

 private:
  const ScriptParams& p_;
  Pose pose_{};
};

constexpr std::size_t kT = 0;  // thumb: front of the fabric, pad facing +n
constexpr std::size_t kI = 1;  // index: back of the fabric, pad facing -n

template <class P>
std::uint8_t Phase(P phase) {
  return static_cast<std::uint8_t>(phase);
}

// kDemo's moves in order.
template <class Visit>
bool VisitDemo(const ScriptParams& p, Visit&& visit) {
  MoveWalk w(p);
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  const Eigen::Vector3d& stretch = p.stretch_D_m;
  w.Start({w.Place(kT, -p.rest_gap_m, none), w.Place(kI, -p.rest_gap_m, none)});

  // settle, then one finger (the thumb) touches the front
  if (w.Straight(Phase(DemoPhase::kSettle), w.pose(), p.hold_s, visit)) return true;
  Pose touch = w.pose();
  touch[kT] = w.Place(kT, p.touch_depth_m, none);
  if (w.Straight(Phase(DemoPhase::kApproach), touch, 0.0, visit)) return true;
  if (w.Straight(Phase(DemoPhase::kTouch), touch, p.hold_s, visit)) return true;
  // the index comes to the back and both squeeze, then both pull along the fabric
  const Pose pinch = {w.Place(kT, p.press_depth_m, none), w.Place(kI, p.press_depth_m, none)};
  if (w.Straight(Phase(DemoPhase::kPinch), pinch, p.hold_s, visit)) return true;
  const Pose stretched = {w.Place(kT, p.press_depth_m, stretch), w.Place(kI, p.press_depth_m, stretch)};
  if (w.Straight(Phase(DemoPhase::kStretch), stretched, p.hold_s, visit)) return true;
  // rub: the thumb to +A, -A, +A, ... (rub_cycles times each way), then back to the middle
  const int strokes = 2 * p.rub_cycles + 1;
  for (int k = 0; k < strokes; ++k) {
    const bool last = k + 1 == strokes;
    const double along_m = last ? 0.0 : (k % 2 == 0 ? p.rub_amplitude_m : -p.rub_amplitude_m);
    Pose rub = stretched;
    rub[kT] += along_m * p.rub_direction_D;
    if (w.Straight(Phase(DemoPhase::kRub), rub, last ? p.hold_s : 0.0, visit)) return true;
  }
  // open the pinch along the normal, then return to the rest pose
  const Pose released = {w.Place(kT, -p.rest_gap_m, stretch), w.Place(kI, -p.rest_gap_m, stretch)};
  if (w.Straight(Phase(DemoPhase::kRelease), released, p.hold_s, visit)) return true;
  const Pose rest = {w.Place(kT, -p.rest_gap_m, none), w.Place(kI, -p.rest_gap_m, none)};
  return w.Straight(Phase(DemoPhase::kRetract), rest, 0.0, visit);
}

// The axis kFold turns the pinch about: the index's distal axis when the fingers lie across a
// hanging fabric, oriented so that a positive angle lifts the thumb over the index.
Eigen::Vector3d FoldAxis(const ScriptParams& p) { return p.up_D.cross(p.fabric_normal_D).normalized(); }

// kFold's moves in order. The turn's pivot is where the index's centre is when its pad just
// touches the fabric plane: the index's target circles it at press_depth_m while the thumb's
// squeeze pushes it back there, so a user on a spring grip keeps the index in place and rolls
// the thumb around it.
template <class Visit>
bool VisitFold(const ScriptParams& p, Visit&& visit) {
  MoveWalk w(p);
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  w.Start({w.Place(kT, -p.rest_gap_m, none), w.Place(kI, -p.rest_gap_m, none)});
  if (w.Straight(Phase(FoldPhase::kSettle), w.pose(), p.hold_s, visit)) return true;
  Pose touch = w.pose();
  touch[kT] = w.Place(kT, p.touch_depth_m, none);
  if (w.Straight(Phase(FoldPhase::kApproach), touch, 0.0, visit)) return true;
  if (w.Straight(Phase(FoldPhase::kTouch), touch, p.hold_s, visit)) return true;
  const Pose pinch = {w.Place(kT, p.press_depth_m, none), w.Place(kI, p.press_depth_m, none)};
  if (w.Straight(Phase(FoldPhase::kPinch), pinch, p.hold_s, visit)) return true;
  // The thumb rises over the index: the fabric below the pinch is carried up and over the index.
  // The fabric above the pinch then wraps the thumb on its way to the pinch; the pair rises by
  // that arc (a finger's radius times the angle), so the fabric between the clamp and the pinch
  // is not stretched by the wrap.
  const Eigen::Vector3d axis = FoldAxis(p);
  const Eigen::Vector3d pivot = w.Place(kI, 0.0, none);
  const Eigen::Vector3d lift = p.pad_offset_m[kT] * std::abs(p.fold_angle_rad) * p.up_D;
  if (w.Turn(Phase(FoldPhase::kFold), pivot, axis, p.fold_angle_rad, lift, p.hold_s, visit)) return true;
  // The fabric above the pinch wraps the thumb from the pinch around its far side; the thumb's
  // free side faces half the fold angle on from where it started, so it leaves along that.
  const Eigen::Vector3d open = Eigen::AngleAxisd(0.5 * p.fold_angle_rad, axis) * -p.fabric_normal_D;
  Pose let_go = w.pose();
  let_go[kT] += (p.press_depth_m + p.rest_gap_m) * open;
  if (w.Straight(Phase(FoldPhase::kLetGo), let_go, p.hold_s, visit)) return true;
  // the fabric lies over the index's top and front: the index leaves downwards and back; the thumb
  // goes back to its own side at the same time, out of the way of the flap that swings back off
  // the index (left where it let go, it was hit by it)
  Pose withdrawn = w.pose();
  withdrawn[kI] += (p.press_depth_m + p.rest_gap_m) * (-p.up_D + p.fabric_normal_D).normalized();
  withdrawn[kT] -= (p.press_depth_m + p.rest_gap_m) * p.fabric_normal_D;
  return w.Straight(Phase(FoldPhase::kWithdraw), withdrawn, p.hold_s, visit);
}

// Where a phased script is at `t_s`: its phase (`done` after the last move), and the targets if
// `out` is not null.
template <class Walk>
std::uint8_t EvaluatePhased(const ScriptParams& p, double t_s, std::uint8_t done, FingerTargets* out, Walk&& walk) {
  double remaining_s = std::max(t_s, 0.0);
  std::uint8_t phase = done;
  Pose last{};
  const bool inside = walk(p, [&](const Move& m) {
    last = m.to;
    if (remaining_s < m.move_s) {
      phase = m.phase;
      if (out != nullptr) Interpolate(m, MinimumJerk(remaining_s, m.move_s), out);
      return true;
    }
    remaining_s -= m.move_s;
    if (remaining_s < m.hold_s) {
      phase = m.phase;
      if (out != nullptr) {
        out->p_D_m = m.to;
        out->v_D_m_per_s = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
      }
      return true;
    }
    remaining_s -= m.hold_s;
    return false;
  });
  if (!inside && out != nullptr) {
    out->p_D_m = last;
    out->v_D_m_per_s = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  }
  return phase;
}

template <class Walk>
double PhasedDuration(const ScriptParams& p, Walk&& walk) {
  double total_s = 0.0;
  walk(p, [&total_s](const Move& m) {
    total_s += m.move_s + m.hold_s;
    return false;
  });
  return total_s;
}

const auto kDemoWalk = [](const ScriptParams& p, auto&& visit) { return VisitDemo(p, visit); };
const auto kFoldWalk = [](const ScriptParams& p, auto&& visit) { return VisitFold(p, visit); };

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
  Require(std::isfinite(fold_angle_rad) && std::abs(fold_angle_rad) <= std::numbers::pi,
          "fold_angle_rad must be in [-pi, pi]");
  if (kind == ScriptKind::kFold) {
    Require(up_D.cross(fabric_normal_D).norm() > 0.5, "kFold needs up_D at least 30 degrees from fabric_normal_D");
  }
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
      const std::size_t rubbing = Slot(p.touch_finger);
      out.p_D_m[rubbing] += p.rub_amplitude_m * std::sin(w * tau_s) * p.rub_direction_D;
      out.v_D_m_per_s[rubbing] += p.rub_amplitude_m * w * std::cos(w * tau_s) * p.rub_direction_D;
      break;
    }
    case ScriptKind::kPlayback:
      Playback(p.trajectory, t_s, &out);
      break;
    case ScriptKind::kDemo:
      EvaluatePhased(p, t_s, Phase(DemoPhase::kDone), &out, kDemoWalk);
      break;
    case ScriptKind::kFold:
      EvaluatePhased(p, t_s, Phase(FoldPhase::kDone), &out, kFoldWalk);
      break;
  }
  return out;
}

DemoPhase DemoPhaseAt(const ScriptParams& params, double t_s) {
  return static_cast<DemoPhase>(EvaluatePhased(params, t_s, Phase(DemoPhase::kDone), nullptr, kDemoWalk));
}

double DemoDuration(const ScriptParams& params) { return PhasedDuration(params, kDemoWalk); }

FoldPhase FoldPhaseAt(const ScriptParams& params, double t_s) {
  return static_cast<FoldPhase>(EvaluatePhased(params, t_s, Phase(FoldPhase::kDone), nullptr, kFoldWalk));
}

double FoldDuration(const ScriptParams& params) { return PhasedDuration(params, kFoldWalk); }

const char* FoldPhaseName(FoldPhase phase) {
  switch (phase) {
    case FoldPhase::kSettle:
      return "settle";
    case FoldPhase::kApproach:
      return "approach";
    case FoldPhase::kTouch:
      return "touch";
    case FoldPhase::kPinch:
      return "pinch";
    case FoldPhase::kFold:
      return "fold";
    case FoldPhase::kLetGo:
      return "let_go";
    case FoldPhase::kWithdraw:
      return "withdraw";
    case FoldPhase::kDone:
      return "done";
  }
  return "unknown";
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
  if (name == "fold") return ScriptKind::kFold;
  throw std::invalid_argument("unknown script '" + name +
                              "' (idle, approach, grasp, pinch, rub, lift, playback, demo or fold)");
}

}  // namespace haptex::device
