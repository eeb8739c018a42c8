#include "libs/tactile/pin_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "libs/base/demand.h"

namespace haptex::tactile {
namespace {

void Require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("RendererConfig: ") + what);
}

const RendererConfig& Validated(const RendererConfig& c) {
  Require(std::isfinite(c.display_rate_hz) && c.display_rate_hz > 0.0, "display_rate_hz must be > 0");
  Require(std::isfinite(c.sample_rate_hz) && c.sample_rate_hz >= c.display_rate_hz,
          "sample_rate_hz must be finite and >= display_rate_hz");
  Require(c.low_primary_hz > 0.0 && c.high_primary_hz > c.low_primary_hz && c.high_primary_hz < 0.5 * c.sample_rate_hz,
          "need 0 < low_primary_hz < high_primary_hz < sample_rate_hz / 2");
  Require(c.envelope_time_constant_s > 0.0 && std::isfinite(c.envelope_time_constant_s),
          "envelope_time_constant_s must be > 0");
  Require(c.footprint_sigma_m >= 0.0 && std::isfinite(c.footprint_sigma_m), "footprint_sigma_m must be >= 0");
  Require(c.anti_alias_factor >= 0.0 && std::isfinite(c.anti_alias_factor), "anti_alias_factor must be >= 0");
  Require(c.slide_stop_speed_m_per_s >= 0.0 && c.slide_start_speed_m_per_s >= c.slide_stop_speed_m_per_s,
          "need 0 <= slide_stop_speed_m_per_s <= slide_start_speed_m_per_s");
  Require(c.max_speed_m_per_s > c.slide_start_speed_m_per_s && std::isfinite(c.max_speed_m_per_s),
          "max_speed_m_per_s must be finite and above slide_start_speed_m_per_s");
  Require(c.max_step_s > 0.0 && std::isfinite(c.max_step_s), "max_step_s must be > 0");
  Require(c.reference_force_N > 0.0 && c.max_force_N > 0.0 && std::isfinite(c.max_force_N),
          "reference_force_N and max_force_N must be > 0");
  Require(c.max_amplitude_40hz_um > 0.0 && c.max_amplitude_320hz_um > 0.0, "display maximum amplitudes must be > 0");
  Require(c.contact_radius_at_reference_force_m > 0.0 && c.max_contact_radius_m > 0.0, "contact radii must be > 0");
  Require(c.layout.pitch_m > 0.0, "layout.pitch_m must be > 0");
  return c;
}

bool Finite(const Eigen::Vector2d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

double ProcessChannel(const ReceptorChannelFilter& filter, double alpha, double height_um, PinChannelState& s) {
  const double y =
      filter.gain_per_um() * s.low_pass.Process(filter.low_pass(), s.high_pass.Process(filter.high_pass(), height_um));
  s.envelope1 += alpha * (y * y - s.envelope1);
  s.envelope2 += alpha * (s.envelope1 - s.envelope2);
  return y;
}

void Prime(const ReceptorChannelFilter& filter, double height_um, PinChannelState& s) {
  s.high_pass.Reset(filter.high_pass(), height_um);
  s.low_pass.Reset(filter.low_pass(), 0.0);  // the high-pass passes no DC
  s.envelope1 = 0.0;
  s.envelope2 = 0.0;
}

void EmitFrame(const RendererModel& model, bool active, double force_gain, FingerRenderState& state,
               const RenderWorkspace& ws) {
  const RendererConfig& c = model.config();
  PinFrame& frame = state.frame;
  for (int k = 0; k < PinLayout::kPinCount; ++k) {
    float lo = 0.0f, hi = 0.0f;
    const auto uk = static_cast<std::size_t>(k);
    if (active && ws.pin_in_contact[uk]) {
      // Envelope of y^2 is half the squared peak excitation of a sinusoid.
      const double e_ra = std::sqrt(2.0 * std::max(0.0, state.ra[uk].envelope2));
      const double e_pc = std::sqrt(2.0 * std::max(0.0, state.pc[uk].envelope2));
      const TactileColour colour = model.matcher().Match(e_ra, e_pc);
      if (colour.out_of_gamut) ++state.counters.out_of_gamut;
      double a_lo = colour.amplitude_low_um * force_gain / c.max_amplitude_40hz_um;
      double a_hi = colour.amplitude_high_um * force_gain / c.max_amplitude_320hz_um;
      if (a_lo > 1.0 || a_hi > 1.0) ++state.counters.amplitude_clamped;
      // Written so that a NaN (which cannot arise from checked input) still ends as 0.
      lo = static_cast<float>(a_lo > 0.0 ? std::min(a_lo, 1.0) : 0.0);
      hi = static_cast<float>(a_hi > 0.0 ? std::min(a_hi, 1.0) : 0.0);
    }
    frame.amplitude_40hz[uk] = lo;
    frame.amplitude_320hz[uk] = hi;
  }
  ++frame.sequence;
}

}  // namespace

RendererModel::RendererModel(const PeriodicTile& fabric, const RendererConfig& config)
    : config_(Validated(config)),
      levels_(MakeLevels(fabric, config_)),
      ra_(config.ra_shape, config.ra_threshold, config.sample_rate_hz),
      pc_(config.pc_shape, config.pc_threshold, config.sample_rate_hz),
      matcher_(ra_.ResponsePerUm(config.low_primary_hz), ra_.ResponsePerUm(config.high_primary_hz),
               pc_.ResponsePerUm(config.low_primary_hz), pc_.ResponsePerUm(config.high_primary_hz)),
      envelope_alpha_(1.0 - std::exp(-2.0 / (config.sample_rate_hz * config.envelope_time_constant_s))),
      samples_per_frame_(config.sample_rate_hz / config.display_rate_hz),
      sample_period_s_(1.0 / config.sample_rate_hz) {}

std::vector<RendererModel::Level> RendererModel::MakeLevels(const PeriodicTile& fabric, const RendererConfig& c) {
  // Level k covers speeds up to v0 2^k with sigma = max(footprint, factor v0 2^k / fs); level 0 is
  // the footprint alone (or covers an eighth of the speed range when there is no footprint).
  const double per_speed = c.anti_alias_factor / c.sample_rate_hz;
  double max_speed =
      c.footprint_sigma_m > 0.0 && per_speed > 0.0 ? c.footprint_sigma_m / per_speed : c.max_speed_m_per_s / 8.0;
  std::vector<Level> levels;
  while (true) {
    const double sigma = std::max(c.footprint_sigma_m, per_speed * max_speed);
    levels.push_back({max_speed, fabric.Smoothed(sigma)});
    if (max_speed >= c.max_speed_m_per_s || per_speed == 0.0 || levels.size() >= 16) break;
    max_speed *= 2.0;
  }
  return levels;
}

void FingerRenderState::Reset() {
  ra = {};
  pc = {};
  has_last_point = false;
  filters_primed = false;
  sliding = false;
  next_sample_in_s = 0.0;
  samples_since_frame = 0.0;
  frame.amplitude_40hz.fill(0.0f);
  frame.amplitude_320hz.fill(0.0f);
}

int RenderStep(const RendererModel& model, const FingerInput& in, double dt_s, FingerRenderState* state,
               RenderWorkspace* ws) {
  HAPTEX_DEMAND(state != nullptr && ws != nullptr);  // a caller bug, not a runtime fault
  const RendererConfig& c = model.config();
  FingerRenderState& s = *state;

  // Time faults: no time passes, or a gap long enough that the path is meaningless.
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) {
    ++s.counters.bad_input;
    return 0;
  }
  if (dt_s > c.max_step_s) {
    ++s.counters.time_gaps;
    s.Reset();
    ws->pin_in_contact.fill(false);
    EmitFrame(model, false, 0.0, s, *ws);
    return 1;
  }

  // Input faults: silence for this step, and the path restarts from the next good point.
  const bool valid = Finite(in.touch_point_m) && Finite(in.slip_velocity_m_per_s) && std::isfinite(in.normal_force_N) &&
                     in.normal_force_N >= 0.0 && std::isfinite(in.orientation_rad) &&
                     std::isfinite(in.contact_radius_m) && in.contact_radius_m >= 0.0;
  bool active = false;
  double force_gain = 0.0;
  double speed_m_per_s = 0.0;
  if (!valid) {
    ++s.counters.bad_input;
    s.has_last_point = false;
    s.sliding = false;
  } else {
    const double speed = in.slip_velocity_m_per_s.norm();
    speed_m_per_s = speed;
    const bool jumped = s.has_last_point && (in.touch_point_m - s.last_point_m).norm() > c.max_speed_m_per_s * dt_s;
    if (speed > c.max_speed_m_per_s || jumped) {
      ++s.counters.absurd_speed;
      s.has_last_point = false;
      s.sliding = false;
    } else {
      s.sliding = s.sliding ? speed > c.slide_stop_speed_m_per_s : speed > c.slide_start_speed_m_per_s;
    }
    if (in.normal_force_N > c.max_force_N) ++s.counters.force_clamped;
    const double force_N = std::min(in.normal_force_N, c.max_force_N);
    force_gain = force_N / c.reference_force_N;
    active = in.in_contact && s.sliding && force_N > 0.0;
  }

  // Pin positions relative to the touch point and which pins lie inside the contact area.
  if (active) {
    double radius_m = in.contact_radius_m;
    if (radius_m == 0.0) {
      radius_m = std::min(c.max_contact_radius_m, c.contact_radius_at_reference_force_m * std::cbrt(force_gain));
    }
    for (int k = 0; k < PinLayout::kPinCount; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      ws->pin_offset_m[uk] = c.layout.OffsetOnFabricM(k, in.orientation_rad);
      ws->pin_in_contact[uk] = ws->pin_offset_m[uk].norm() <= radius_m;
    }
  } else {
    ws->pin_in_contact.fill(false);
    s.filters_primed = false;
  }

  const PeriodicTile& fabric = model.FabricForSpeed(speed_m_per_s);

  // A new slide starts from the current point with filters in steady state: no start-up click.
  const Eigen::Vector2d end_point = valid ? in.touch_point_m : s.last_point_m;
  if (active && (!s.filters_primed || !s.has_last_point)) {
    for (int k = 0; k < PinLayout::kPinCount; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      const Eigen::Vector2d p = end_point + ws->pin_offset_m[uk];
      const double h = fabric.HeightUm(p.x(), p.y());
      Prime(model.ra_filter(), h, s.ra[uk]);
      Prime(model.pc_filter(), h, s.pc[uk]);
    }
    s.filters_primed = true;
    s.last_point_m = end_point;
    s.has_last_point = true;
  }

  // Internal samples inside this step, on the path interpolated linearly between touch points.
  const Eigen::Vector2d start_point = s.last_point_m;
  const double h = model.sample_period_s();
  const double alpha = model.envelope_alpha();
  int frames = 0;
  double t = s.next_sample_in_s;
  while (t <= dt_s) {
    if (active) {
      const Eigen::Vector2d p = start_point + (end_point - start_point) * (t / dt_s);
      for (int k = 0; k < PinLayout::kPinCount; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        const double height_um = fabric.HeightUm(p.x() + ws->pin_offset_m[uk].x(), p.y() + ws->pin_offset_m[uk].y());
        ProcessChannel(model.ra_filter(), alpha, height_um, s.ra[uk]);
        ProcessChannel(model.pc_filter(), alpha, height_um, s.pc[uk]);
      }
    }
    s.samples_since_frame += 1.0;
    if (s.samples_since_frame >= model.samples_per_frame()) {
      s.samples_since_frame -= model.samples_per_frame();
      EmitFrame(model, active, force_gain, s, *ws);
      ++frames;
    }
    t += h;
  }
  s.next_sample_in_s = t - dt_s;
  // Off the fabric the point is not tracked, so touching down elsewhere is not a jump.
  if (valid && in.in_contact) {
    s.last_point_m = in.touch_point_m;
    s.has_last_point = true;
  } else {
    s.has_last_point = false;
  }
  return frames;
}

}  // namespace haptex::tactile
