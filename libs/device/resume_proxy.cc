#include "libs/device/resume_proxy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace haptex::device {
namespace {

void Require(bool ok, const char* field, const char* rule, double value) {
  if (!ok) {
    throw std::invalid_argument(std::string("ResumeProxyConfig: ") + field + " " + rule + ", got " +
                                std::to_string(value));
  }
}

bool NonNegativeFinite(double v) { return v >= 0.0 && std::isfinite(v); }

}  // namespace

void ResumeProxyConfig::Validate() const {
  Require(held_window_s > 0.0 && held_window_s <= 1.0, "held_window_s", "must be in (0, 1] s", held_window_s);
  Require(NonNegativeFinite(min_held_N), "min_held_N", "must be >= 0 N", min_held_N);
  Require(bound_ratio >= 1.0 && std::isfinite(bound_ratio), "bound_ratio", "must be >= 1", bound_ratio);
  Require(NonNegativeFinite(bound_margin_N), "bound_margin_N", "must be >= 0 N", bound_margin_N);
  Require(NonNegativeFinite(watch_s), "watch_s", "must be >= 0 s", watch_s);
  Require(NonNegativeFinite(settle_s), "settle_s", "must be >= 0 s", settle_s);
  Require(release_rate_N_per_s > 0.0 && std::isfinite(release_rate_N_per_s), "release_rate_N_per_s", "must be > 0 N/s",
          release_rate_N_per_s);
  Require(NonNegativeFinite(release_max_s), "release_max_s", "must be >= 0 s", release_max_s);
  Require(NonNegativeFinite(spring_N_per_m), "spring_N_per_m", "must be >= 0 N/m", spring_N_per_m);
  Require(NonNegativeFinite(damping_N_s_per_m), "damping_N_s_per_m", "must be >= 0 N s/m", damping_N_s_per_m);
  Require(NonNegativeFinite(rejoin_m), "rejoin_m", "must be >= 0 m", rejoin_m);
  Require(NonNegativeFinite(contact_end_N), "contact_end_N", "must be >= 0 N", contact_end_N);
  Require(late_model_s > 0.0 && std::isfinite(late_model_s), "late_model_s", "must be > 0 s", late_model_s);
  Require(NonNegativeFinite(late_watch_s), "late_watch_s", "must be >= 0 s", late_watch_s);
  Require(late_factor >= 1.0 && std::isfinite(late_factor), "late_factor", "must be >= 1", late_factor);
}

void HeldForceWindow::Add(double force_N, double dt_s, double window_s) {
  const double bucket_s = window_s / static_cast<double>(kBuckets);
  if (time_s_[current_] >= bucket_s) {
    current_ = (current_ + 1) % kBuckets;
    sum_N_s_[current_] = 0.0;
    time_s_[current_] = 0.0;
  }
  sum_N_s_[current_] += force_N * dt_s;
  time_s_[current_] += dt_s;
}

double HeldForceWindow::Mean() const {
  double sum = 0.0, time = 0.0;
  for (std::size_t i = 0; i < kBuckets; ++i) {
    sum += sum_N_s_[i];
    time += time_s_[i];
  }
  return time > 0.0 ? sum / time : 0.0;
}

void HeldForceWindow::Clear() {
  sum_N_s_.fill(0.0);
  time_s_.fill(0.0);
  current_ = 0;
}

ResumeProxy::ResumeProxy(const ResumeProxyConfig& config, double max_cut_s) : config_(config), max_cut_s_(max_cut_s) {
  config_.Validate();
  Require(NonNegativeFinite(max_cut_s), "max_cut_s", "must be >= 0 s", max_cut_s);
}

double ResumeProxy::bound_N() const {
  const double releasing_s = std::max(0.0, since_cut_s_ - config_.watch_s);
  return std::max(config_.bound_ratio * held_N_, held_N_ + config_.bound_margin_N) +
         config_.release_rate_N_per_s * releasing_s;
}

void ResumeProxy::EndContact() {
  phase_ = Phase::kFollowing;
  proxy_active_ = false;
  window_.Clear();
  has_whole_ = false;
}

bool ResumeProxy::BeginTick(bool cut, double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) dt_s = 0.0;
  if (cut) {
    if (phase_ == Phase::kFollowing) {
      const double held_N = window_.Mean();
      if (!has_whole_ || held_N < config_.min_held_N || last_whole_W_N_.norm() <= 0.0) return false;
      held_N_ = held_N;
      surface_p_W_m_ = last_whole_p_W_m_;
      inward_W_ = -last_whole_W_N_.normalized();
      phase_ = Phase::kCut;
      proxy_active_ = true;
      rejoined_s_ = -1.0;
      // a cut noticed after a stall of our own lasted up to this tick's period
      cut_s_ = dt_s;
      since_cut_s_ = dt_s;
      peak_since_cut_N_ = asked_since_cut_N_ = 0.0;
      limited_since_cut_ = false;
      ++cuts_;
      if (cut_s_ > max_cut_s_) {
        ++contacts_ended_;
        EndContact();
      }
      return true;
    }
    if (phase_ == Phase::kResuming) {  // cut again before the return was over: the proxy holds again
      proxy_active_ = true;
      rejoined_s_ = -1.0;
    }
    phase_ = Phase::kCut;
    cut_s_ += dt_s;
    since_cut_s_ += dt_s;
    if (cut_s_ > max_cut_s_) {
      ++contacts_ended_;
      EndContact();
    }
    return false;
  }
  if (phase_ == Phase::kCut) {
    phase_ = Phase::kResuming;
  } else if (phase_ == Phase::kResuming) {
    since_cut_s_ += dt_s;
    if (!proxy_active_) rejoined_s_ = std::max(rejoined_s_, 0.0) + dt_s;
    // past watch_s only a finger still behind the surface keeps the proxy (the bound rising)
    const bool watched = since_cut_s_ >= config_.watch_s && !proxy_active_;
    if (watched || rejoined_s_ >= config_.settle_s || since_cut_s_ >= config_.watch_s + config_.release_max_s) {
      EndContact();
    }
  }
  return false;
}

Eigen::Vector3d ResumeProxy::Constrain(const Eigen::Vector3d& p_W_m) const {
  if (!constraining()) return p_W_m;
  const double depth_m = (p_W_m - surface_p_W_m_).dot(inward_W_);
  return depth_m > 0.0 ? Eigen::Vector3d(p_W_m - depth_m * inward_W_) : p_W_m;
}

Eigen::Vector3d ResumeProxy::Shape(const Eigen::Vector3d& model_at_proxy_W_N, const Eigen::Vector3d& p_W_m,
                                   const Eigen::Vector3d& v_W_m_per_s) {
  if (phase_ == Phase::kFollowing) return model_at_proxy_W_N;
  Eigen::Vector3d force = model_at_proxy_W_N.allFinite() ? model_at_proxy_W_N : Eigen::Vector3d::Zero();
  const double depth_m = (p_W_m - surface_p_W_m_).dot(inward_W_);
  if (proxy_active_ && depth_m > 0.0) {
    const double inward_speed = v_W_m_per_s.allFinite() ? v_W_m_per_s.dot(inward_W_) : 0.0;
    force -= (config_.spring_N_per_m * depth_m + config_.damping_N_s_per_m * inward_speed) * inward_W_;
  }
  // contact pushes: nothing of the force may pull the finger into the surface
  const double inward_N = force.dot(inward_W_);
  if (inward_N > 0.0) force -= inward_N * inward_W_;
  if (phase_ == Phase::kResuming) {
    if (proxy_active_ && depth_m <= config_.rejoin_m) proxy_active_ = false;  // back on the surface
    if (depth_m <= 0.0 && model_at_proxy_W_N.norm() < config_.contact_end_N) {
      EndContact();  // the finger has left the contact
      return force;
    }
  }
  asked_since_cut_N_ = std::max(asked_since_cut_N_, force.norm());
  const double bound = bound_N();
  if (force.norm() > bound) {
    force *= bound / force.norm();
    limited_since_cut_ = true;
  }
  return force;
}

Eigen::Vector3d ResumeProxy::CapLateModel(const Eigen::Vector3d& force, double model_age_s, double dt_s) {
  if (!config_.cap_late_models) return force;
  const bool late = model_age_s > std::max(config_.late_model_s, config_.late_factor * longest_gap_s_);
  if (late && !late_) late_held_N_ = window_.Mean();  // what the hand held before
  if (late) late_watch_left_s_ = config_.late_watch_s;
  late_ = late;
  if (!late) late_watch_left_s_ = std::max(0.0, late_watch_left_s_ - (std::isfinite(dt_s) ? dt_s : 0.0));
  if (phase_ != Phase::kFollowing || !has_whole_ || !(late || late_watch_left_s_ > 0.0)) return force;
  const double held_N = late_held_N_;
  if (held_N < config_.min_held_N) return force;
  const double bound = std::max(config_.bound_ratio * held_N, held_N + config_.bound_margin_N);
  const double norm = force.norm();
  if (!(norm > bound)) return force;
  ++late_model_caps_;
  return force * (bound / norm);
}

Eigen::Vector3d ResumeProxy::ClampToBound(const Eigen::Vector3d& force) {
  if (phase_ == Phase::kFollowing) return force;
  const double bound = bound_N(), norm = force.norm();
  if (!(norm > bound)) return force;
  limited_since_cut_ = true;
  return force * (bound / norm);
}

void ResumeProxy::OnModelArrival(double interval_s) {
  if (!(interval_s >= 0.0) || !std::isfinite(interval_s)) return;
  longest_gap_s_ = std::max(interval_s, longest_gap_s_ * std::exp(-interval_s / 1.0));
}

void ResumeProxy::EndTick(const Eigen::Vector3d& commanded_W_N, const Eigen::Vector3d& p_W_m, bool whole_force,
                          double dt_s) {
  if (phase_ != Phase::kFollowing) {
    // the bound's second: what the release after it gives is the squeeze's, not the resume's
    if (since_cut_s_ <= config_.watch_s) peak_since_cut_N_ = std::max(peak_since_cut_N_, commanded_W_N.norm());
    return;
  }
  if (!whole_force || !(dt_s > 0.0) || !std::isfinite(dt_s)) return;
  window_.Add(commanded_W_N.norm(), dt_s, config_.held_window_s);
  last_whole_W_N_ = commanded_W_N;
  last_whole_p_W_m_ = p_W_m;
  has_whole_ = true;
}

}  // namespace haptex::device
