#pragma once
// What a run's recordings and the mock controller's force log say: contact-state histogram,
// forces per finger, and the plots (gnuplot, PNG). A plot whose data is absent is skipped with
// the reason, which the summary lists.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "haptex/v1/scene.pb.h"
#include "launch/recording.h"

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
  std::string name;     // "forces", "friction_ratio", "force_vs_elongation", "loop_periods"
  std::string file;     // the PNG, when drawn
  std::string skipped;  // why not, when not drawn
};

/// Writes the plots into run_dir/plots (data files beside them). Never throws for missing data;
/// a gnuplot failure is a skipped plot with the reason.
std::vector<PlotResult> MakePlots(const std::string& run_dir, const v1::Scene& scene,
                                  const std::vector<Recording>& recordings, const std::optional<ForceLog>& force_log);

}  // namespace haptex::launch
