#include "services/in_process/stall_response.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace haptex::in_process {
namespace {

// I alone, then the static and dynamic state of each situation together (II/III, ..., VIII/IX)
int Situation(contact::ContactState s) { return static_cast<int>(s) / 2; }

// The largest swing of one component through zero within the window ending at each sample, from
// at least kSideN one way to at least kSideN the other: a buzz, not a force that falls to zero (a
// slip, a release) and overshoots by a trace.
constexpr double kSideN = 0.25;
class ReversalMeter {
 public:
  explicit ReversalMeter(std::size_t window_ticks) : window_ticks_(std::max<std::size_t>(window_ticks, 1)) {}
  void Add(const Eigen::Vector3d& f) {
    history_.push_back(f);
    if (history_.size() > window_ticks_ + 1) history_.pop_front();
    for (int k = 0; k < 3; ++k) {
      const double now = f[k];
      for (const Eigen::Vector3d& before : history_) {
        if ((before[k] >= kSideN && now <= -kSideN) || (before[k] <= -kSideN && now >= kSideN)) {
          largest_ = std::max(largest_, std::abs(before[k] - now));
        }
      }
    }
  }
  double largest() const { return largest_; }

 private:
  std::size_t window_ticks_;
  std::deque<Eigen::Vector3d> history_;
  double largest_ = 0.0;
};

}  // namespace

double ResumeBoundN(double held_N) { return std::max(1.1 * held_N, held_N + 0.3); }

StallResponse MeasureStall(const scene::LoadedScene& scene, const Stall& stall, const StallResponseOptions& options,
                           std::vector<StallTraceSample>* trace) {
  InProcessSystem system(scene, options.links);
  if (stall.duration_s > 0.0) system.AddStall(stall);
  const double held_from_s = stall.at_s - options.held_window_s;
  const double end_s = stall.at_s + stall.duration_s;
  const double watch_to_s = end_s + options.watch_after_s;
  const auto window_ticks = static_cast<std::size_t>(std::lround(options.reversal_window_s / system.dt_s()));
  std::array<ReversalMeter, 2> reversals{ReversalMeter(window_ticks), ReversalMeter(window_ticks)};
  std::array<double, 2> held_sum{};
  std::array<Eigen::Vector3d, 2> previous_N{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<Eigen::Vector3d, 2> held_p_m{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<Eigen::Vector3d, 2> window_start_p_m{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  bool window_started = false;
  int held_n = 0;
  StallResponse r;
  double holding_since_s = -1.0;
  while (system.t_s() < watch_to_s) {
    const double t = system.t_s();
    if (t >= stall.at_s - 1e-9 && !r.pinched_before && t < stall.at_s + system.dt_s() / 2) {
      r.state_before = system.local_contact().contact_state();
      r.pinched_before = Situation(r.state_before) == Situation(contact::ContactState::kVIII);
    }
    system.Step();
    const contact::ContactState state = system.local_contact().contact_state();
    if (t >= held_from_s && t < stall.at_s - 1e-9) {
      for (int f = 0; f < 2; ++f) held_sum[static_cast<std::size_t>(f)] += system.finger(f).commanded_N.norm();
      if (!window_started) {
        for (int f = 0; f < 2; ++f) window_start_p_m[static_cast<std::size_t>(f)] = system.finger(f).position_m;
        window_started = true;
      }
      ++held_n;
    }
    if (t >= held_from_s && trace != nullptr) {
      StallTraceSample& s = trace->emplace_back();
      s.t_s = t;
      s.state = state;
      for (int f = 0; f < 2; ++f) {
        s.commanded_N[static_cast<std::size_t>(f)] = system.finger(f).commanded_N;
        s.position_m[static_cast<std::size_t>(f)] = system.finger(f).position_m;
      }
    }
    if (t < stall.at_s - 1e-9) {
      for (int f = 0; f < 2; ++f) {
        previous_N[static_cast<std::size_t>(f)] = system.finger(f).commanded_N;
        held_p_m[static_cast<std::size_t>(f)] = system.finger(f).position_m;
      }
      continue;
    }
    if (held_n > 0 && r.fingers[0].held_N == 0.0 && r.fingers[1].held_N == 0.0) {
      for (std::size_t f = 0; f < 2; ++f) r.fingers[f].held_N = held_sum[f] / held_n;
    }
    bool at_held = Situation(state) == Situation(r.state_before) && r.state_before != contact::ContactState::kI;
    for (int f = 0; f < 2; ++f) {
      const auto i = static_cast<std::size_t>(f);
      FingerStallResponse& fr = r.fingers[i];
      const Eigen::Vector3d& F = system.finger(f).commanded_N;
      fr.peak_after_N = std::max(fr.peak_after_N, F.norm());
      // a cut is immediate by design (FORCE_ENABLE clear): the slew limit is the resume's
      if (!F.isZero(0.0) && !previous_N[i].isZero(0.0)) {
        fr.largest_step_N = std::max(fr.largest_step_N, (F - previous_N[i]).cwiseAbs().maxCoeff());
      }
      previous_N[i] = F;
      reversals[i].Add(F);
      fr.largest_reversal_N = reversals[i].largest();
      // a finger at rest before must be back where it was; one that moved (a rub) only feel the same
      const bool at_rest = (held_p_m[i] - window_start_p_m[i]).norm() < 0.001;
      at_held = at_held && std::abs(F.norm() - fr.held_N) <= options.hold_tolerance * std::max(fr.held_N, 0.5) &&
                (!at_rest || (system.finger(f).position_m - held_p_m[i]).norm() <= options.hold_position_m);
    }
    if (t >= end_s - 1e-9 && !std::isfinite(r.held_again_after_s)) {
      if (!at_held) {
        holding_since_s = -1.0;
      } else {
        if (holding_since_s < 0.0) holding_since_s = t;
        if (t - holding_since_s >= options.hold_confirm_s - 1e-9) r.held_again_after_s = holding_since_s - end_s;
      }
    }
  }
  for (const FingerStallResponse& f : r.fingers) {
    if (f.held_N >= 0.5)
      r.worst_peak_over_bound = std::max(r.worst_peak_over_bound, f.peak_after_N / ResumeBoundN(f.held_N));
  }
  const device::DeviceBridge& bridge = system.bridge().bridge();
  r.tick_gap_disarms = bridge.counters().tick_gap_disarms;
  r.tick_gaps_held = bridge.counters().tick_gaps_held;
  r.stale_model_cuts = bridge.counters().stale_model_cuts;
  r.device_lost_events = bridge.counters().device_lost_events;
  r.host_timeouts = system.mock().controller().counters().host_timeouts;
  r.world_pauses = system.mock().controller().counters().world_pauses;
  return r;
}

}  // namespace haptex::in_process
