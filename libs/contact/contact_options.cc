#include "libs/contact/contact_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace haptex::contact {
namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("ContactOptions: " + what);
}

void CheckShape(const FingerShape& s, const std::string& name) {
  Require(std::isfinite(s.radius_m) && s.radius_m > 0.0 && s.radius_m < 0.05,
          name + ".radius_m must be in (0, 0.05) m");
  Require(std::isfinite(s.length_m) && s.length_m >= 0.0 && s.length_m < 0.1, name + ".length_m must be in [0, 0.1) m");
}

void CheckMu(const FrictionCoefficients& mu, const std::string& name) {
  Require(std::isfinite(mu.mu_static) && mu.mu_static >= 0.0 && mu.mu_static <= 10.0,
          name + ".mu_static must be in [0, 10]");
  Require(std::isfinite(mu.mu_dynamic) && mu.mu_dynamic >= 0.0 && mu.mu_dynamic <= mu.mu_static,
          name + ".mu_dynamic must be in [0, mu_static]");
}

void CheckPositive(double v, const std::string& name) {
  Require(std::isfinite(v) && v > 0.0, name + " must be positive and finite");
}

}  // namespace

void ValidateContactOptions(const ContactOptions& o) {
  CheckShape(o.thumb, "thumb");
  CheckShape(o.index, "index");
  Require(
      std::isfinite(o.fabric_half_thickness_m) && o.fabric_half_thickness_m >= 0.0 && o.fabric_half_thickness_m < 0.005,
      "fabric_half_thickness_m must be in [0, 0.005) m");
  CheckMu(o.finger_fabric, "finger_fabric");
  CheckMu(o.finger_finger, "finger_finger");
  CheckPositive(o.finger_finger_normal_N_per_m, "finger_finger_normal_N_per_m");
  CheckPositive(o.finger_finger_tangential_N_per_m, "finger_finger_tangential_N_per_m");
  CheckPositive(o.pad_stiffness_N_per_m3, "pad_stiffness_N_per_m3");
  Require(o.pinch_samples_per_edge >= 1 && o.pinch_samples_per_edge <= 8, "pinch_samples_per_edge must be in [1, 8]");
  Require(std::isfinite(o.touch_release_gap_m) && o.touch_release_gap_m >= 0.0, "touch_release_gap_m must be >= 0");
  Require(o.dynamic_leave_fraction > 0.0 && o.dynamic_leave_fraction <= o.dynamic_enter_fraction &&
              o.dynamic_enter_fraction <= 1.0,
          "need 0 < dynamic_leave_fraction <= dynamic_enter_fraction <= 1");
  CheckPositive(o.textile_contact_force_N, "textile_contact_force_N");
  Require(std::isfinite(o.state_filter_s) && o.state_filter_s >= 0.0 && o.state_filter_s <= 1.0,
          "state_filter_s must be in [0, 1] s");
  Require(std::isfinite(o.pinch_edge_ramp_m) && o.pinch_edge_ramp_m >= 0.0 && o.pinch_edge_ramp_m < 0.005,
          "pinch_edge_ramp_m must be in [0, 0.005) m");
  CheckPositive(o.max_finger_force_N, "max_finger_force_N");
  CheckPositive(o.max_stiffness_N_per_m, "max_stiffness_N_per_m");
  CheckPositive(o.stiffness_filter_s, "stiffness_filter_s");
}

}  // namespace haptex::contact
