#pragma once
// What a run's recordings and the mock controller's force log say: contact-state histogram,
// forces per finger, and the plots (gnuplot, PNG), among them the paper's Fig. 9 and Fig. 10
// measured against their references. A plot whose data is absent is skipped with the reason,
// which the summary lists.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "launch/recording.h"
#include "libs/scene/scene_loader.h"

namespace haptex::launch {

struct FingerForceStats {
  std::uint64_t samples = 0;
  double peak_n = 0;
  double mean_n = 0;
  double final_n = 0;  // the last sample
};

/// The mock controller's force log (time_ns, per finger commanded and applied force, ...).
struct ForceLog {
  std::vector<double> t_s;                       // from the first row
  std::array<std::vector<double>, 2> commanded;  // |F| per finger (thumb, index) [N]
  std::array<FingerForceStats, 2> stats;         // of the commanded force
  /// Force dropouts: the commanded force cut to zero from kDropoutFromN or more between two log
  /// rows (a watchdog, a stall guard, an emergency stop), which a person feels as the object
  /// vanishing; the ramps of a model going stale come down over 10 ms and are not counted.
  static constexpr double kDropoutFromN = 0.5;
  std::uint64_t dropouts = 0;
};

/// Reads the CSV; nullopt when the file is missing or has no rows.
std::optional<ForceLog> ReadForceLog(const std::string& path);

struct RecordingAnalysis {
  std::array<std::uint64_t, 10> contact_states{};        // ForceModel samples per state (0: unspecified, 1..9: I..IX)
  std::map<std::string, FingerForceStats> model_forces;  // |F0| per finger name
  std::uint64_t force_models = 0, touch_traces = 0, health_messages = 0, finger_states = 0;
};

RecordingAnalysis AnalyseRecordings(const std::vector<Recording>& recordings);

/// Roman numeral of a contact state 1..9 ("I".."IX").
std::string RomanState(int state);

struct PlotResult {
  PlotResult() = default;
  PlotResult(std::string name_, std::string file_, std::string skipped_)
      : name(std::move(name_)), file(std::move(file_)), skipped(std::move(skipped_)) {}

  std::string name;     // "forces", "friction_ratio", "force_vs_elongation", "loop_periods"
  std::string file;     // the PNG, when drawn
  std::string skipped;  // why not, when not drawn
  /// What the figure measures (the paper's figures against their references), in summary.json
  /// under the plot, and `note` says it in a line (printed at the end of the run).
  std::vector<std::pair<std::string, double>> measured;
  std::string note;
};

/// Fig. 10's strip: the fabric clamped along a line across the stretch, the fingers pinching it.
struct ClampedStrip {
  double clamp_along_stretch_m = 0.0;  ///< the clamp line's coordinate along the stretch direction (W)
  double width_m = 0.0;                ///< the fabric's extent across the stretch
  std::string direction;               ///< "warp" or "weft": which tensile curve the stretch loads
  std::function<double(double strain)> force_per_width_N_per_m;
};

/// What the paper's figures are measured against, from the scene and its fabric.
struct FigureReference {
  bool has_friction = false;  ///< the finger-fabric coefficients below are the scene's (Fig. 9)
  double mu_static = 0.0, mu_dynamic = 0.0;
  Eigen::Vector3d stretch_W{Eigen::Vector3d::UnitX()};  ///< unit: where the mock user pulls a pinch
  std::optional<ClampedStrip> strip;                    ///< Fig. 10's tensile strip, when the scene is one
  std::string no_strip;                                 ///< why not, otherwise
};

/// The friction, the stretch direction and, when the cloth is a strip clamped across the stretch
/// and narrow enough for the fingers to grip across, that strip. @throws std::invalid_argument
/// when the scene's fabric or device cannot be converted (the services would refuse it too).
FigureReference FigureReferenceFromScene(const scene::LoadedScene& scene);

/// Writes the plots into run_dir/plots (data files beside them). Never throws for missing data;
/// a gnuplot failure is a skipped plot with the reason.
std::vector<PlotResult> MakePlots(const std::string& run_dir, const v1::Scene& scene,
                                  const std::vector<Recording>& recordings, const std::optional<ForceLog>& force_log,
                                  const FigureReference& reference = {});

}  // namespace haptex::launch
