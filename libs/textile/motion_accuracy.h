#pragma once
// Accuracy in motion: a 20 x 20 cm cloth in three motions (released swing, pushed and
// released, pinched and stretched), each run with a solver setting and compared with a
// converged reference on the same mesh (bench/textile/dynamic_accuracy, the dynamics
// validation test, docs/fabric-model.md "Accuracy in motion"). Part of
// haptex::textile_validation, like validation.h.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/step_options.h"

namespace haptex::textile::validation {

enum class MotionKind {
  kSwing,  ///< held along one edge, horizontal, let go: it falls and swings under the stand
  kPush,   ///< hanging, pushed normal to itself with twice its weight on a 2 cm disc for 0.25 s, released
  /// hanging, pushed normal to itself with twice its weight spread over every free particle (by
  /// mass) for 0.25 s, released: a whole-cloth load, without the disc's local spike of strain
  kPushWhole,
  kPinch,  ///< hanging, gripped on a 2 cm disc by stiff springs and stretched 1 cm sideways in 0.5 s
};

/// "swing", "push", "push_whole", "pinch". @throws std::invalid_argument naming the choices.
MotionKind MotionKindNamed(const std::string& name);
const char* MotionKindName(MotionKind kind);

struct Motion {
  MotionKind kind = MotionKind::kSwing;
  double duration_s = 1.0;
  double release_s = 0.0;  ///< no work is done on the cloth after this (but by gravity and drag)
  FabricState start;
  std::vector<int> gripped;        ///< push: the loaded particles; pinch: the gripped ones
  std::vector<double> push_share;  ///< push: each loaded particle's part of push_W_N (they sum to 1)
  Eigen::Vector3d push_W_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d stretch_W_m = Eigen::Vector3d::Zero();
  double stretch_s = 0.0;
};

/// The converged reference's solver: BDF2, Newton to 1e-8 (reassembled), CG to 1e-8, no splitting.
StepOptions ConvergedOptions(double dt_s);

/// The cloth hanging from its top row (warp down) after settling 0.5 s with ConvergedOptions at
/// 1 ms, at rest: the common start of the hanging motions.
FabricState SettledHanging(const FabricModel& model);

Motion MakeMotion(MotionKind kind, const FabricModel& model, const FabricState& settled_hanging);

/// What a run records: every millisecond (or every step when steps are longer) the positions,
/// total energy and largest strain; the largest strain over every step; the solver's counts.
struct MotionTrace {
  double dt_s = 0.0;
  std::vector<Eigen::VectorXd> x_W_m;
  std::vector<double> energy_J;
  std::vector<double> largest_strain;
  double peak_strain = 0.0;
  double newton_iterations_per_step = 0.0;
  double cg_iterations_per_step = 0.0;
  std::int64_t step_halvings = 0, newton_not_converged = 0, nan_events = 0;
};

/// Runs the motion with `options`; `step` takes each step (a benchmark times it there).
MotionTrace RunMotion(const Motion& motion, const FabricModel& model, const StepOptions& options,
                      const std::function<StepResult(FabricStepper&, FabricState&)>& step = {});

struct MotionErrors {
  double peak_strain_pct = 0.0;     ///< |peak - reference's peak| / reference's peak
  double strain_in_time_pct = 0.0;  ///< largest |strain(t) - reference's| / reference's peak
  double position_rms_mm = 0.0;     ///< RMS over particles and samples of |x - x_ref|
  double energy_pct = 0.0;          ///< largest |E - E_ref| / the reference's energy range
  double energy_growth_pct = 0.0;   ///< largest rise of E after the release, same scale
};

/// `run` against `reference` at the times both sampled (the reference's steps must divide the run's).
MotionErrors CompareMotion(const Motion& motion, const MotionTrace& run, const MotionTrace& reference);

}  // namespace haptex::textile::validation
