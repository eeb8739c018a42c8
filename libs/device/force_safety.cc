#include "libs/device/force_safety.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

// Times closer than this count as equal, so a ramp that ends at 20 ms ends at the tick that
// falls on 20 ms despite rounding in t_s.
constexpr double kTimeTolerance_s = 1e-7;

void Require(bool ok, const char* field, const std::string& rule, double value) {
  if (!ok) {
    throw std::invalid_argument(std::string("ForceSafetyConfig: ") + field + " " + rule + ", got " +
                                std::to_string(value));
  }
}

// Scales `v` down to magnitude `max_norm` if longer; direction kept. Exactly zero if max_norm <= 0.
bool ClampNorm(double max_norm, Eigen::Vector3d* v) {
  if (max_norm <= 0.0) {
    const bool changed = !v->isZero(0.0);
    v->setZero();
    return changed;
  }
  const double n = v->norm();
  if (n <= max_norm) return false;
  *v *= max_norm / n;
  return true;
}

}  // namespace

void ForceSafetyConfig::Validate() const {
  Require(peak_force_N > 0.0 && peak_force_N <= kDevicePeakForce_N, "peak_force_N",
          "must be in (0, " + std::to_string(kDevicePeakForce_N) + "] N (device peak)", peak_force_N);
  Require(
      continuous_force_N > 0.0 && continuous_force_N <= kDeviceContinuousForce_N && continuous_force_N <= peak_force_N,
      "continuous_force_N", "must be in (0, min(peak_force_N, 6 N)]", continuous_force_N);
  Require(continuous_window_s > 0.0 && std::isfinite(continuous_window_s), "continuous_window_s", "must be > 0 s",
          continuous_window_s);
  Require(slew_N_per_tick > 0.0 && std::isfinite(slew_N_per_tick), "slew_N_per_tick", "must be > 0 N", slew_N_per_tick);
  Require(slew_N_per_s > 0.0 && std::isfinite(slew_N_per_s), "slew_N_per_s", "must be > 0 N/s", slew_N_per_s);
  Require(stale_after_s > 0.0, "stale_after_s", "must be > 0 s", stale_after_s);
  Require(stale_ramp_s >= 0.0, "stale_ramp_s", "must be >= 0 s", stale_ramp_s);
  Require(stale_after_s + stale_ramp_s <= kMaxForceModelSilence_s + 1e-12, "stale_after_s + stale_ramp_s",
          "must be <= 0.020 s (zero force 20 ms after the last model)", stale_after_s + stale_ramp_s);
  Require(startup_ramp_s >= 0.0 && std::isfinite(startup_ramp_s), "startup_ramp_s", "must be >= 0 s", startup_ramp_s);
  Require(resume_ramp_s >= 0.0 && std::isfinite(resume_ramp_s), "resume_ramp_s", "must be >= 0 s", resume_ramp_s);
  Require(resume_within_m >= 0.0 && std::isfinite(resume_within_m), "resume_within_m", "must be >= 0 m",
          resume_within_m);
  Require(resume_within_s >= 0.0 && std::isfinite(resume_within_s), "resume_within_s", "must be >= 0 s",
          resume_within_s);
}

ForceSafety::ForceSafety(const ForceSafetyConfig& config) : config_(config) { config_.Validate(); }

void ForceSafety::Reset() {
  counters_ = SafetyCounters{};
  previous_W_N_.setZero();
  mean_square_N2_ = 0.0;
  armed_s_ = 0.0;
  resumable_ = false;
  interrupted_s_ = 0.0;
  armed_p_W_m_.setZero();
}

double ForceSafety::rms_force_N() const { return std::sqrt(mean_square_N2_); }

double ForceSafety::WatchdogGain(const SafetyInput& input) const {
  if (!(input.model_age_s >= 0.0) || !std::isfinite(input.model_age_s)) return 0.0;
  // a model with no (or a broken) ttl is stale on arrival
  const double ttl_s = std::isfinite(input.model_ttl_s) ? std::max(input.model_ttl_s, 0.0) : 0.0;
  const double fresh_s = std::min(ttl_s, config_.stale_after_s);
  const double staleness_s = input.model_age_s - fresh_s;
  if (staleness_s <= 0.0) return 1.0;
  if (staleness_s >= config_.stale_ramp_s - kTimeTolerance_s) return 0.0;
  return 1.0 - staleness_s / config_.stale_ramp_s;
}

SafetyOutput ForceSafety::Step(const SafetyInput& input, double dt_s) {
  ++counters_.steps;
  SafetyOutput out;
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) dt_s = 0.0;

  // NaN/Inf guard
  Eigen::Vector3d target = input.requested_W_N;
  if (!target.allFinite()) {
    ++counters_.non_finite;
    target.setZero();
  }

  // watchdog and start-up ramps; any forced zero disarms, so force always ramps back in
  const double watchdog_gain = WatchdogGain(input);
  if (watchdog_gain < 1.0) ++counters_.stale_steps;
  if (watchdog_gain <= 0.0) ++counters_.watchdog_zero_steps;
  if (!input.output_allowed || watchdog_gain <= 0.0) {
    armed_s_ = 0.0;
    // a brief interruption of a fully armed stage (the link to the controller, or the models
    // falling silent while output was allowed: a paused host) with the finger still where it had
    // force resumes over resume_ramp_s; anything else (device lost, stopped, held, an interruption
    // beyond resume_within_s or resume_within_m) ramps in over startup_ramp_s
    interrupted_s_ += dt_s;
    const bool brief_cause = input.link_interruption || input.output_allowed;
    const bool held_still = (input.p_W_m - armed_p_W_m_).norm() <= config_.resume_within_m;
    if (!brief_cause || !held_still || interrupted_s_ > config_.resume_within_s + kTimeTolerance_s) {
      resumable_ = false;
    }
  } else {
    armed_s_ += dt_s;
  }
  const double ramp_s = resumable_ ? std::min(config_.resume_ramp_s, config_.startup_ramp_s) : config_.startup_ramp_s;
  const double startup_gain = ramp_s > 0.0 ? std::min(1.0, armed_s_ / ramp_s) : 1.0;
  if (input.output_allowed && watchdog_gain > 0.0 && armed_s_ >= ramp_s - kTimeTolerance_s) {
    resumable_ = true;
    interrupted_s_ = 0.0;
  }
  const double gain = input.output_allowed ? watchdog_gain * startup_gain : 0.0;
  // where the user held the finger against the whole force (not while a stale model fades)
  if (gain >= 1.0) armed_p_W_m_ = input.p_W_m;
  out.ramping = gain < 1.0;
  target *= gain;

  // continuous limit: the allowed magnitude falls linearly from the peak (cold) to the
  // continuous limit as the mean square approaches c^2, so bursts may use the peak, the RMS
  // converges to c from below, and the cap moves far slower than the slew limit (no step)
  const double c = config_.continuous_force_N;
  const double c2 = c * c;
  const double budget = std::clamp((c2 - mean_square_N2_) / c2, 0.0, 1.0);
  const double continuous_cap_N = c + (config_.peak_force_N - c) * budget;
  const double a = 1.0 - std::exp(-dt_s / config_.continuous_window_s);

  // peak and continuous magnitude limits, direction kept
  const double cap_N = std::min(config_.peak_force_N, continuous_cap_N);
  const double requested_N = target.norm();
  if (requested_N > config_.peak_force_N) ++counters_.peak_limited;
  if (requested_N > continuous_cap_N && continuous_cap_N < config_.peak_force_N) {
    ++counters_.continuous_limited;
  }
  if (ClampNorm(cap_N, &target)) out.limited = true;

  // slew limit per unit of time and per step
  Eigen::Vector3d delta = target - previous_W_N_;
  if (ClampNorm(std::min(config_.slew_N_per_tick, config_.slew_N_per_s * dt_s), &delta)) {
    out.limited = true;
    ++counters_.slew_limited;
  }
  Eigen::Vector3d force = previous_W_N_ + delta;

  // final envelope: only ever shrinks the force, so ramps and limits hold exactly
  ClampNorm(cap_N * gain, &force);

  mean_square_N2_ += a * (force.squaredNorm() - mean_square_N2_);
  previous_W_N_ = force;
  out.force_W_N = force;
  return out;
}

}  // namespace haptex::device
