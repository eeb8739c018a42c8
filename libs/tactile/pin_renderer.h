#pragma once
// Real-time tactile rendering (docs/tactile.md section 6, the filter bank): for each pin, the
// height under it along the finger's path on the periodic fabric, two receptor-channel filters,
// energy envelopes, tactile-colour matching, force scaling and the display's range.
//
// Model (read-only, built once) / FingerRenderState (per finger, mutable, fixed size) /
// RenderWorkspace (scratch, fixed size). RenderStep never allocates, throws or reads a clock.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "libs/tactile/periodic_tile.h"
#include "libs/tactile/pin_frame.h"
#include "libs/tactile/pin_layout.h"
#include "libs/tactile/receptor_filter.h"
#include "libs/tactile/tactile_colour.h"

namespace haptex::tactile {

struct RendererConfig {
  /// Pin amplitude frames per second.
  double display_rate_hz = 500.0;
  /// Internal rate at which the surface is sampled along the path and filtered.
  double sample_rate_hz = 4000.0;
  double low_primary_hz = 40.0;
  double high_primary_hz = 320.0;
  ThresholdCurve ra_threshold = ThresholdCurve::DefaultRa();
  ThresholdCurve pc_threshold = ThresholdCurve::DefaultPc();
  ReceptorChannelShape ra_shape = DefaultRaShape();
  ReceptorChannelShape pc_shape = DefaultPcShape();
  /// Time constant of the energy envelope (two cascaded one-pole stages of half this each).
  double envelope_time_constant_s = 0.015;
  /// Gaussian pin/skin footprint applied to the fabric at model construction (0 = none).
  double footprint_sigma_m = 0.1e-3;
  /// Anti-aliasing: at speed v the fabric is band-limited with a Gaussian of at least
  /// anti_alias_factor * v / sample_rate_hz (0.68: -20 dB at the Nyquist wavelength), taken from
  /// pre-smoothed levels whose sigma doubles (like mip-mapping).
  double anti_alias_factor = 0.68;
  /// Sliding hysteresis on the slip speed: starts above start, stops below stop.
  double slide_start_speed_m_per_s = 2e-3;
  double slide_stop_speed_m_per_s = 1e-3;
  /// Slip speeds (or jumps of the touch point) above this are faults: silence and a count.
  double max_speed_m_per_s = 1.0;
  /// Steps longer than this are gaps: the path restarts, one silent frame.
  double max_step_s = 0.05;
  /// Amplitudes scale with normal_force / reference_force (force clamped to max_force_N).
  double reference_force_N = 1.0;
  double max_force_N = 20.0;
  /// Display range per primary [um peak]: 1.0 in PinFrame. A placeholder (docs/tactile.md section 2).
  double max_amplitude_40hz_um = 50.0;
  double max_amplitude_320hz_um = 50.0;
  /// Contact radius when the input gives none: r_ref (N / reference_force)^(1/3), at most max.
  double contact_radius_at_reference_force_m = 4e-3;
  double max_contact_radius_m = 8e-3;
  PinLayout layout;
};

/// One finger's contact with the fabric, in fabric coordinates (u = warp, v = weft).
struct FingerInput {
  Eigen::Vector2d touch_point_m = Eigen::Vector2d::Zero();
  /// Velocity of the finger relative to the fabric surface, fabric frame.
  Eigen::Vector2d slip_velocity_m_per_s = Eigen::Vector2d::Zero();
  double normal_force_N = 0.0;
  /// Angle from the fabric's u axis to the finger's long (6-pin) axis.
  double orientation_rad = 0.0;
  /// Radius of the contact area around the touch point; 0 = derive from the normal force.
  double contact_radius_m = 0.0;
  bool in_contact = false;
};

/// Faults and limits hit, counted per finger (never reset by RenderStep).
struct RenderCounters {
  std::uint64_t bad_input = 0;          ///< NaN/Inf fields, negative force or radius, dt <= 0
  std::uint64_t absurd_speed = 0;       ///< slip speed or touch-point jump above max_speed
  std::uint64_t time_gaps = 0;          ///< dt > max_step_s
  std::uint64_t force_clamped = 0;      ///< steps with force above max_force_N
  std::uint64_t amplitude_clamped = 0;  ///< pin amplitudes cut at the display maximum
  std::uint64_t out_of_gamut = 0;       ///< pins whose colour needed a gamut fix
};

/// Read-only renderer model: configuration, smoothed fabric, designed filters.
class RendererModel final {
 public:
  /// @throws std::invalid_argument with the offending field on a bad configuration.
  RendererModel(const PeriodicTile& fabric, const RendererConfig& config = {});

  const RendererConfig& config() const { return config_; }
  /// The fabric as smoothed by the footprint (level 0).
  const PeriodicTile& fabric() const { return levels_.front().tile; }
  /// The fabric level band-limited for sliding at speed_m_per_s. Real-time safe.
  const PeriodicTile& FabricForSpeed(double speed_m_per_s) const {
    for (const Level& level : levels_) {
      if (speed_m_per_s <= level.max_speed_m_per_s) return level.tile;
    }
    return levels_.back().tile;
  }
  int level_count() const { return static_cast<int>(levels_.size()); }
  const ReceptorChannelFilter& ra_filter() const { return ra_; }
  const ReceptorChannelFilter& pc_filter() const { return pc_; }
  const ColourMatcher& matcher() const { return matcher_; }
  double envelope_alpha() const { return envelope_alpha_; }
  double samples_per_frame() const { return samples_per_frame_; }
  double sample_period_s() const { return sample_period_s_; }

 private:
  struct Level {
    double max_speed_m_per_s;
    PeriodicTile tile;
  };
  static std::vector<Level> MakeLevels(const PeriodicTile& fabric, const RendererConfig& config);

  RendererConfig config_;
  std::vector<Level> levels_;
  ReceptorChannelFilter ra_;
  ReceptorChannelFilter pc_;
  ColourMatcher matcher_;
  double envelope_alpha_;
  double samples_per_frame_;
  double sample_period_s_;
};

/// Filter and envelope state of one channel of one pin.
struct PinChannelState {
  BiquadState high_pass;
  BiquadState low_pass;
  double envelope1 = 0.0;
  double envelope2 = 0.0;  ///< smoothed squared excitation [threshold units^2]
};

/// Mutable per-finger state; fixed size, so it never allocates.
struct FingerRenderState {
  std::array<PinChannelState, PinLayout::kPinCount> ra{};
  std::array<PinChannelState, PinLayout::kPinCount> pc{};
  Eigen::Vector2d last_point_m = Eigen::Vector2d::Zero();
  bool has_last_point = false;
  bool filters_primed = false;
  bool sliding = false;
  double next_sample_in_s = 0.0;  ///< time from the end of the last step to the next sample
  double samples_since_frame = 0.0;
  PinFrame frame;  ///< newest frame
  RenderCounters counters;

  /// Back to silence (keeps counters and the frame sequence).
  void Reset();
};

/// Scratch for one step.
struct RenderWorkspace {
  std::array<Eigen::Vector2d, PinLayout::kPinCount> pin_offset_m;
  std::array<bool, PinLayout::kPinCount> pin_in_contact{};
};

/// Advances one finger by dt_s with the newest input. Returns the number of display frames
/// completed in this step (the newest is state->frame). Never allocates or throws; faulty input
/// gives silence and a count.
int RenderStep(const RendererModel& model, const FingerInput& input, double dt_s, FingerRenderState* state,
               RenderWorkspace* workspace);

}  // namespace haptex::tactile
