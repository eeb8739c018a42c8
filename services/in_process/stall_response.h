#pragma once
// What a pause of the host does to the hand: a scene runs in one process (services/in_process) with
// one stall, and each finger's commanded force after it is compared with the force it held before:
// the peak against the resume bound, the largest sign reversal of a component (a buzz), and how
// long the pinch takes to hold again. The stall test and the stall sweep (bench/stall) share it.

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "libs/contact/contact_state.h"
#include "libs/scene/scene_loader.h"
#include "services/in_process/in_process_system.h"

namespace haptex::in_process {

struct StallResponseOptions {
  double held_window_s = 0.100;  ///< the force held: its mean over this long before the stall
  double watch_after_s = 1.0;    ///< the response: from the stall's start to this long after its end
  /// Held again: the contact is in its situation of before the stall (a pinch: VIII or IX) with
  /// forces within this share of the force held (at least of 0.5 N), and fingers that were at rest
  /// within hold_position_m of where they were, for hold_confirm_s on end.
  double hold_tolerance = 0.10;
  double hold_position_m = 0.001;
  double hold_confirm_s = 0.020;
  double reversal_window_s = 0.010;  ///< a component swinging through zero within this long
  LinkImpairments links;
};

/// The resume bound of a finger that held `held_N`: 1.1 x held, or held + 0.3 N when larger.
double ResumeBoundN(double held_N);

struct FingerStallResponse {
  double held_N = 0.0;        ///< mean |F| over held_window_s before the stall
  double peak_after_N = 0.0;  ///< largest |F| while watched
  /// Largest swing of one component through zero within reversal_window_s while watched: from
  /// 0.25 N or more one way to 0.25 N or more the other, the two magnitudes summed [N] (a force
  /// falling to zero, a slip or a release, is no reversal).
  double largest_reversal_N = 0.0;
  /// Largest change of one component from one 0.2 ms tick to the next while watched, between
  /// ticks that both have force (a cut to zero is immediate by design).
  double largest_step_N = 0.0;
};

struct StallResponse {
  std::array<FingerStallResponse, 2> fingers{};
  contact::ContactState state_before = contact::ContactState::kI;  ///< when the stall began
  bool pinched_before = false;                                     ///< VIII or IX when the stall began
  /// From the stall's end to the start of the first hold_confirm_s in the situation of before (VIII
  /// or IX for a pinch; I is none) at the force held (infinity: not within watch_after_s).
  double held_again_after_s = std::numeric_limits<double>::infinity();
  // what the run counted
  std::uint64_t tick_gap_disarms = 0, tick_gaps_held = 0, stale_model_cuts = 0, host_timeouts = 0,
                device_lost_events = 0, world_pauses = 0, limited_resumes = 0;
  /// Largest peak_after_N / ResumeBoundN(held_N) over the fingers that held 0.5 N or more (0: none).
  double worst_peak_over_bound = 0.0;
};

/// One sample per 0.2 ms tick, for plots and inspection.
struct StallTraceSample {
  double t_s = 0.0;
  std::array<Eigen::Vector3d, 2> commanded_N{};
  std::array<Eigen::Vector3d, 2> position_m{};
  contact::ContactState state = contact::ContactState::kI;
};

/// Runs `scene` from its start to the end of the watch with `stall` (duration_s 0: none).
/// `trace`, when given, gets every tick of the watch and of held_window_s before it.
StallResponse MeasureStall(const scene::LoadedScene& scene, const Stall& stall, const StallResponseOptions& options,
                           std::vector<StallTraceSample>* trace = nullptr);

}  // namespace haptex::in_process
