#pragma once
// Scripted "artificial user" for the mock GRAB controller: where each fingertip wants to be over
// time. The mock pulls the fingers toward these targets; the rendered force pushes back.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "libs/device/grab_protocol.h"
#include "libs/device/trajectory_csv.h"

namespace haptex::device {

enum class ScriptKind : std::uint8_t {
  kIdle,              ///< both fingers rest in front of / behind the fabric
  kApproachAndTouch,  ///< one finger moves to the fabric and presses lightly
  kGraspAndSqueeze,   ///< both fingers close on the fabric and squeeze it
  kPinchAndStretch,   ///< grasp, then move both fingers along stretch_D_m
  kRub,               ///< grasp, then touch_finger slides back and forth while squeezing
  kLift,              ///< grasp, then lift both fingers
  kPlayback,          ///< follow a recorded trajectory (ScriptParams::trajectory)
  kDemo,              ///< touch, pinch, stretch, rub, release in sequence (DemoPhase)
  kFold,              ///< pinch, fold the fabric over the index while pinched, let go with the thumb (FoldPhase)
};

/// The phases of kDemo, in the order the script visits them. Each move is a minimum-jerk move
/// whose peak speed is ScriptParams::speed_m_per_s; the moves marked "then hold" are followed by
/// a pause of ScriptParams::hold_s at their end pose.
enum class DemoPhase : std::uint8_t {
  kSettle,    ///< both fingers at rest off the fabric, for hold_s
  kApproach,  ///< the thumb moves to the fabric's front and its pad presses touch_depth_m into it
  kTouch,     ///< one finger touches: the thumb holds, for hold_s
  kPinch,     ///< the index comes to the back; both pads aim press_depth_m past the fabric; then hold
  kStretch,   ///< both fingers move by stretch_D_m; then hold
  kRub,       ///< still pinched, the thumb strokes rub_cycles times +-rub_amplitude_m; then hold
  kRelease,   ///< both fingers back off to rest_gap_m on their sides; then hold
  kRetract,   ///< both fingers return (undoing the stretch) to their rest pose
  kDone,      ///< at rest, for good
};

/// The phases of kFold (paper section 5.4: the fabric folded over one finger while pinched), in
/// order. Moves and holds as in kDemo.
enum class FoldPhase : std::uint8_t {
  kSettle,    ///< both fingers at rest off the fabric, for hold_s
  kApproach,  ///< the thumb moves to the fabric's front and its pad presses touch_depth_m into it
  kTouch,     ///< one finger touches: the thumb holds, for hold_s
  kPinch,     ///< the index comes to the back; both pads aim press_depth_m past the fabric; then hold
  kFold,      ///< the pinched pair turns by fold_angle_rad about the index's axis, the thumb rising
              ///< over it, so the fabric below the pinch wraps the index; then hold
  kLetGo,     ///< the thumb opens away from the index and out of the fabric's wrap; the index
              ///< alone holds the folded fabric; then hold
  kWithdraw,  ///< the index moves down and back, out from under the draped fabric, and the thumb
              ///< back to its own side; then hold
  kDone,      ///< at rest, for good
};

/// Script parameters, filled by the scene. Geometry in the device workspace frame D
/// (docs/grab-protocol.md). Validate() throws std::invalid_argument with a clear message.
struct ScriptParams {
  ScriptKind kind = ScriptKind::kIdle;
  Eigen::Vector3d fabric_point_D_m{Eigen::Vector3d::Zero()};  ///< where the fingers meet the fabric
  /// Unit normal of the fabric, from the thumb's (front) side to the index's (back) side.
  Eigen::Vector3d fabric_normal_D{0.0, 1.0, 0.0};
  double rest_gap_m = 0.030;         ///< each finger's distance from the fabric at rest
  double approach_duration_s = 1.0;  ///< rest -> touching the fabric
  double press_duration_s = 0.3;     ///< touching -> pressed by press_depth_m
  double press_depth_m = 0.004;      ///< target beyond the fabric plane (how hard the user presses)
  /// Which finger kApproachAndTouch presses and kRub strokes (a scene with the index alone rubs
  /// with it: stroking a finger the scene does not simulate would leave the fabric untouched).
  Manipulator touch_finger = Manipulator::kThumb;
  Eigen::Vector3d stretch_D_m{0.010, 0.0, 0.0};  ///< kPinchAndStretch displacement
  double stretch_duration_s = 1.0;
  Eigen::Vector3d rub_direction_D{1.0, 0.0, 0.0};  ///< kRub slide direction (unit, in the fabric)
  double rub_amplitude_m = 0.010;
  double rub_frequency_Hz = 2.0;
  double lift_height_m = 0.030;         ///< kLift, along up_D
  Eigen::Vector3d up_D{0.0, 0.0, 1.0};  ///< against gravity (unit): W's +z seen in D
  double lift_duration_s = 1.0;
  std::vector<TrajectorySample> trajectory;  ///< kPlayback samples (strictly increasing t_s)
  // kDemo only (the other kinds keep their durations above):
  double speed_m_per_s = 0.05;   ///< peak speed of every move of each finger
  double hold_s = 0.5;           ///< pause between phases
  double touch_depth_m = 0.002;  ///< how far past the fabric plane the touching pad aims
  int rub_cycles = 2;            ///< back-and-forth strokes of the rub
  // kFold only: how far the pinched pair turns about the index's axis, which is up_D x
  // fabric_normal_D (the fingers' distal axis when they lie across a hanging fabric).
  double fold_angle_rad = 130.0 * std::numbers::pi / 180.0;
  /// Distance from each fingertip's centre (the position the device reports) to its pad, along
  /// the pad normal; kDemo aims the pads, so rest_gap_m, touch_depth_m and press_depth_m are pad
  /// distances. Index by Manipulator. The other kinds aim the centres.
  std::array<double, kManipulatorCount> pad_offset_m{0.0, 0.0};

  void Validate() const;
};

/// The kind a name on the command line means: idle, approach, grasp, pinch, rub, lift, playback,
/// demo or fold. @throws std::invalid_argument naming the choices for anything else.
ScriptKind ScriptKindFromName(const std::string& name);

/// Target position and velocity of each finger (index by Manipulator), frame D.
struct FingerTargets {
  std::array<Eigen::Vector3d, kManipulatorCount> p_D_m{};
  std::array<Eigen::Vector3d, kManipulatorCount> v_D_m_per_s{};
};

/// Targets at script time `t_s` (t_s < 0 is treated as 0; after the script ends the last pose is
/// held). No allocation. @pre params.Validate() passed.
FingerTargets EvaluateScript(const ScriptParams& params, double t_s);

/// The kDemo phase at script time `t_s` (whatever params.kind is). @pre params.Validate() passed.
DemoPhase DemoPhaseAt(const ScriptParams& params, double t_s);

/// When kDemo reaches DemoPhase::kDone. @pre params.Validate() passed.
double DemoDuration(const ScriptParams& params);

/// "settle", "approach", "touch", "pinch", "stretch", "rub", "release", "retract", "done".
const char* DemoPhaseName(DemoPhase phase);

/// The kFold phase at script time `t_s` (whatever params.kind is). @pre params.Validate() passed.
FoldPhase FoldPhaseAt(const ScriptParams& params, double t_s);

/// When kFold reaches FoldPhase::kDone. @pre params.Validate() passed.
double FoldDuration(const ScriptParams& params);

/// "settle", "approach", "touch", "pinch", "fold", "let_go", "withdraw", "done".
const char* FoldPhaseName(FoldPhase phase);

}  // namespace haptex::device
