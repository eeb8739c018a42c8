#include "libs/contact/contact_solver.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace haptex::contact {
namespace {

constexpr FrictionCoefficients kNoFriction{0.0, 0.0};

bool Finite(const FingerPose& pose) { return pose.p_W_m.allFinite() && pose.R_WF.allFinite(); }

// Scales K so its largest |eigenvalue| is at most max (K symmetric).
Eigen::Matrix3d CapStiffness(const Eigen::Matrix3d& k, double max_N_per_m) {
  const Eigen::Matrix3d sym = 0.5 * (k + k.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(sym, Eigen::EigenvaluesOnly);
  const double largest = eig.eigenvalues().cwiseAbs().maxCoeff();
  if (!std::isfinite(largest)) return Eigen::Matrix3d::Zero();
  return largest > max_N_per_m ? Eigen::Matrix3d(sym * (max_N_per_m / largest)) : sym;
}

}  // namespace

ContactSolver::ContactSolver(const textile::FabricModel& patch, const ContactOptions& options,
                             const Eigen::Vector2d& uv_origin_m)
    : patch_(patch),
      options_((ValidateContactOptions(options), options)),
      rest_uv_m_(patch.num_particles, 2),
      particle_triangle_(static_cast<std::size_t>(patch.num_particles), 0),
      springs_(patch.num_particles),
      pinch_owned_(static_cast<std::size_t>(patch.num_particles), 0),
      finger_fabric_{FingerFabricContact(patch.area_m2, options.thumb, options),
                     FingerFabricContact(patch.area_m2, options.index, options)},
      finger_finger_(options),
      pinch_(patch, options),
      stiffness_{SecantStiffness(options.max_stiffness_N_per_m, options.stiffness_filter_s),
                 SecantStiffness(options.max_stiffness_N_per_m, options.stiffness_filter_s)},
      on_textile_{FilteredHysteresis(options.textile_contact_force_N, 0.5 * options.textile_contact_force_N,
                                     options.state_filter_s, FilteredHysteresis::Rise::kAtOnce),
                  FilteredHysteresis(options.textile_contact_force_N, 0.5 * options.textile_contact_force_N,
                                     options.state_filter_s, FilteredHysteresis::Rise::kAtOnce)},
      dynamic_(options.dynamic_enter_fraction, options.dynamic_leave_fraction, options.state_filter_s),
      touching_(0.0, -options.touch_release_gap_m),
      particle_force_W_N_(Eigen::VectorXd::Zero(3 * patch.num_particles)),
      force_particles_(static_cast<std::size_t>(patch.num_particles), 0) {
  for (int p = 0; p < patch.num_particles; ++p) {
    rest_uv_m_.row(p) = (patch.mesh.rest_uv_m(p) + uv_origin_m).transpose();
  }
  for (std::size_t t = patch.triangles.size(); t-- > 0;) {
    for (int p : patch.triangles[t].p) particle_triangle_[static_cast<std::size_t>(p)] = static_cast<int>(t);
  }
}

void ContactSolver::Reset() {
  for (auto& f : finger_fabric_) f.Reset();
  finger_finger_.Reset();
  pinch_.Reset();
  for (auto& s : stiffness_) s.Reset();
  for (auto& h : on_textile_) h.Reset();
  dynamic_.Reset();
  touching_.Reset();
  have_previous_ = {false, false};
  pinching_ = false;
  output_ = ContactOutput{};
}

void ContactSolver::ContinueFrom(const ContactSolver& other) {
  stiffness_ = other.stiffness_;
  on_textile_ = other.on_textile_;
  dynamic_ = other.dynamic_;
  touching_ = other.touching_;
  previous_pose_ = other.previous_pose_;
  have_previous_ = other.have_previous_;
  output_.state = other.output_.state;
  output_.evidence = other.output_.evidence;
  output_.ticks = other.output_.ticks;
}

void ContactSolver::Prepare(const FingerInput& thumb, const FingerInput& index, double dt_s,
                            textile::FabricState* state) {
  dt_s_ = dt_s;
  input_ = {thumb, index};
  for (auto& in : input_) {
    if (in.present && !Finite(in.pose)) {
      in.present = false;
      ++diagnostics_.non_finite_inputs;
    }
  }
  springs_.Clear();
  std::fill(pinch_owned_.begin(), pinch_owned_.end(), std::uint8_t{0});
  output_.finger_finger = FingerFingerResult{};

  // Both fingers: squeezing fabric (VIII/IX) or touching each other (II/III)?
  pinching_ = false;
  if (input_[kThumb].present && input_[kIndex].present) {
    Eigen::Vector3d n;
    const double gap_direct =
        FingerFingerContact::Gap(options_, input_[kThumb].pose, input_[kIndex].pose, &n, nullptr, nullptr);
    const double gap_fabric = gap_direct - 2.0 * options_.fabric_half_thickness_m;
    if (gap_fabric < 0.0) {
      const double grip_N = options_.finger_finger_normal_N_per_m * -gap_fabric;
      pinching_ = pinch_.Prepare(input_[kThumb].pose, input_[kIndex].pose, grip_N, options_.finger_fabric, *state,
                                 &pinch_owned_, &springs_);
    }
    if (!pinching_) pinch_.Reset();
    output_.finger_finger = pinching_ ? finger_finger_.Update(input_[kThumb].pose, input_[kIndex].pose,
                                                              2.0 * options_.fabric_half_thickness_m,
                                                              options_.finger_finger, /*with_friction=*/false)
                                      : finger_finger_.Update(input_[kThumb].pose, input_[kIndex].pose, 0.0,
                                                              options_.finger_finger, /*with_friction=*/true);
    touching_.Update(pinching_ ? -gap_fabric : -gap_direct);
  } else {
    pinch_.Reset();
    finger_finger_.Reset();
    touching_.Reset();
  }

  for (int f = 0; f < 2; ++f) {
    if (input_[static_cast<std::size_t>(f)].present) {
      // Outside the pinch area a pinched fabric slides freely over the finger (paper 5.4). The
      // pinch's reach contains the finger's own (one more half thickness): beyond it, no contact.
      const std::uint8_t excluded = kPinchOwnedBit | (f == kThumb ? kPinchBeyondThumbBit : kPinchBeyondIndexBit);
      finger_fabric_[static_cast<std::size_t>(f)].Prepare(
          input_[static_cast<std::size_t>(f)].pose, *state, pinch_owned_,
          pinching_ ? kNoFriction : options_.finger_fabric, &springs_, excluded);
    } else {
      finger_fabric_[static_cast<std::size_t>(f)].Reset();
    }
  }
  springs_.WriteTo(state);
}

const ContactOutput& ContactSolver::Resolve(const textile::FabricState& state) {
  ++output_.ticks;
  // The force each particle felt during the step, exactly as the integrator applied it: only
  // the particles Prepare gave springs have one (the integrator skips k = 0); the others keep
  // or get back +0.
  for (int i = 0; i < num_force_particles_; ++i) {
    particle_force_W_N_.segment<3>(3 * force_particles_[static_cast<std::size_t>(i)]).setZero();
  }
  num_force_particles_ = springs_.num_touched();
  for (int i = 0; i < num_force_particles_; ++i) {
    const int p = springs_.touched(i);
    force_particles_[static_cast<std::size_t>(i)] = p;
    particle_force_W_N_.segment<3>(3 * p) =
        state.anchor_stiffness_N_per_m[p] * (state.anchor_W_m.segment<3>(3 * p) - state.x_W_m.segment<3>(3 * p));
  }
  std::array<FingerFabricResult, 2> one{};
  for (int f = 0; f < 2; ++f) {
    if (!input_[static_cast<std::size_t>(f)].present) continue;
    finger_fabric_[static_cast<std::size_t>(f)].Resolve(input_[static_cast<std::size_t>(f)].pose, state, rest_uv_m_,
                                                        &one[static_cast<std::size_t>(f)]);
  }
  pinch_.Resolve(state, rest_uv_m_, &output_.pinch);
  const PinchResult& pinch = output_.pinch;
  const FingerFingerResult& ff = output_.finger_finger;

  // Evidence and the state.
  ContactEvidence& ev = output_.evidence;
  for (int f = 0; f < 2; ++f) {
    const double load = one[static_cast<std::size_t>(f)].normal_sum_N + (pinch.active ? pinch.grip_N : 0.0);
    FilteredHysteresis& on_textile = on_textile_[static_cast<std::size_t>(f)];
    if (!input_[static_cast<std::size_t>(f)].present) on_textile.Reset();  // no history for an absent finger
    const bool on = input_[static_cast<std::size_t>(f)].present && on_textile.Update(load, dt_s_);
    (f == kThumb ? ev.thumb_on_textile : ev.index_on_textile) = on;
  }
  ev.fingers_touch = touching_.on() || pinch.active;
  double slip_fraction = 0.0;
  if (pinch.active) {
    slip_fraction = pinch.samples > 0 ? static_cast<double>(pinch.sliding_samples) / pinch.samples : 0.0;
  } else if (ev.fingers_touch && !ev.thumb_on_textile && !ev.index_on_textile) {
    slip_fraction = ff.sliding ? 1.0 : 0.0;
  } else {
    const double total = one[0].normal_sum_N + one[1].normal_sum_N;
    slip_fraction = total > 0.0 ? (one[0].sliding_normal_N + one[1].sliding_normal_N) / total : 0.0;
  }
  ev.slip_fraction = slip_fraction;
  ev.dynamic = dynamic_.Update(slip_fraction, dt_s_);
  output_.state = Classify(ev);

  // Per finger: force, stiffness, touch.
  for (int f = 0; f < 2; ++f) {
    FingerContactOutput& out = output_.finger[static_cast<std::size_t>(f)];
    out = FingerContactOutput{};
    const FingerInput& in = input_[static_cast<std::size_t>(f)];
    if (!in.present) {
      stiffness_[static_cast<std::size_t>(f)].Reset();
      have_previous_[static_cast<std::size_t>(f)] = false;
      continue;
    }
    const FingerFabricResult& r = one[static_cast<std::size_t>(f)];
    const double sign = f == kIndex ? 1.0 : -1.0;  // finger-finger and grip act along +-n
    Eigen::Vector3d fabric_force = r.force_W_N;
    if (pinch.active) fabric_force -= 0.5 * pinch.fabric_force_W_N;
    Eigen::Vector3d force = fabric_force + sign * ff.force_on_index_W_N;
    out.contact_particles = r.particles;
    out.on_textile = f == kThumb ? ev.thumb_on_textile : ev.index_on_textile;

    if (!force.allFinite()) {
      ++diagnostics_.non_finite_forces;
      force.setZero();
      fabric_force.setZero();
    }
    const double magnitude = force.norm();
    if (magnitude > options_.max_finger_force_N) {
      force *= options_.max_finger_force_N / magnitude;
      out.force_clamped = true;
      ++diagnostics_.force_clamps;
    }
    out.force_W_N = force;

    // Contact normal, outward from the finger.
    if (pinch.active || (ff.touching && r.particles == 0)) {
      out.contact_normal_W = -sign * (pinch.active ? pinch.normal_W : ff.normal_W);
    } else {
      out.contact_normal_W = r.normal_W;
    }
    const double fn = -force.dot(out.contact_normal_W);
    out.normal_force_N = std::max(0.0, fn);
    out.tangential_force_N = (force + fn * out.contact_normal_W).norm();
    if (out.normal_force_N > 0.0) {
      double mu = pinch.active || r.particles > 0 ? options_.finger_fabric.mu_static : 0.0;
      if (ff.touching) mu = std::max(mu, options_.finger_finger.mu_static);
      out.friction_cone_mu = std::max(mu, out.tangential_force_N / out.normal_force_N);
    }

    if (pinch.active) {
      out.friction_normal_N = pinch.grip_N;
      out.friction_tangential_N = 0.5 * pinch.friction_W_N.norm();
    } else if (r.particles > 0) {
      out.friction_normal_N = r.law_load.normal_N;
      out.friction_tangential_N = r.law_load.tangential_N;
    } else if (ff.touching) {
      out.friction_normal_N = ff.normal_N;
      out.friction_tangential_N = ff.tangential_N;
    }

    // Stiffness: the finger-finger spring is known; the fabric's is measured.
    const double k_fabric = stiffness_[static_cast<std::size_t>(f)].Update(fabric_force, in.pose.p_W_m, dt_s_);
    Eigen::Matrix3d k = -k_fabric * Eigen::Matrix3d::Identity();
    if (ff.touching) k += ff.stiffness_index_W_N_per_m;
    out.stiffness_W_N_per_m = CapStiffness(k, options_.max_stiffness_N_per_m);
    // the spring between the fingers acts on their distance: d F_this / d x_other = -d F_this / d x_this
    if (ff.touching)
      out.cross_stiffness_W_N_per_m = CapStiffness(-ff.stiffness_index_W_N_per_m, options_.max_stiffness_N_per_m);

    // Touch point and slip, for the tactile renderer.
    const Eigen::Vector3d finger_velocity =
        have_previous_[static_cast<std::size_t>(f)] && dt_s_ > 0.0
            ? Eigen::Vector3d((in.pose.p_W_m - previous_pose_[static_cast<std::size_t>(f)].p_W_m) / dt_s_)
            : Eigen::Vector3d::Zero();
    if (out.on_textile) {
      int triangle = -1;
      Eigen::Vector3d fabric_velocity = Eigen::Vector3d::Zero();
      if (pinch.active && pinch.samples > 0) {
        out.touch_uv_m = pinch.touch_uv_m;
        triangle = pinch.touch_triangle;
        fabric_velocity = pinch.touch_velocity_W;
      } else if (r.particles > 0) {
        out.touch_uv_m = r.touch_uv_m;
        triangle = particle_triangle_[static_cast<std::size_t>(r.strongest_particle)];
        fabric_velocity = r.touch_velocity_W;
      }
      if (triangle >= 0) {
        out.touching = true;
        TouchFrame(triangle, state, in.pose, finger_velocity - fabric_velocity, &out);
      }
    }
    previous_pose_[static_cast<std::size_t>(f)] = in.pose;
    have_previous_[static_cast<std::size_t>(f)] = true;
  }
  return output_;
}

void ContactSolver::TouchFrame(int triangle, const textile::FabricState& state, const FingerPose& pose,
                               const Eigen::Vector3d& relative_velocity_W, FingerContactOutput* out) const {
  // Deformed warp and weft vectors (dx/du, dx/dv) of the triangle under the touch point.
  const textile::TriangleElement& e = patch_.triangles[static_cast<std::size_t>(triangle)];
  Eigen::Matrix<double, 3, 2> j = Eigen::Matrix<double, 3, 2>::Zero();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d x = state.x_W_m.segment<3>(3 * e.p[static_cast<std::size_t>(k)]);
    j.col(0) += e.a[static_cast<std::size_t>(k)] * x;
    j.col(1) += e.b[static_cast<std::size_t>(k)] * x;
  }
  const Eigen::Matrix2d jtj = j.transpose() * j;
  if (!(std::abs(jtj.determinant()) > 1e-12)) return;
  const Eigen::Matrix2d inv = jtj.inverse();
  out->slip_uv_m_per_s = inv * (j.transpose() * relative_velocity_W);
  const Eigen::Vector2d axis = inv * (j.transpose() * pose.R_WF.col(0));
  out->finger_angle_rad = std::atan2(axis.y(), axis.x());
}

}  // namespace haptex::contact
