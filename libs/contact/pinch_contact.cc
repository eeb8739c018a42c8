#include "libs/contact/pinch_contact.h"

#include <algorithm>
#include <cmath>

#include "libs/contact/coulomb_friction.h"
#include "libs/contact/finger_finger_contact.h"

namespace haptex::contact {

PinchContact::PinchContact(const textile::FabricModel& patch, const ContactOptions& options)
    : patch_(patch),
      options_(options),
      radius_thumb_m_(options.thumb.radius_m + options.fabric_half_thickness_m),
      radius_index_m_(options.index.radius_m + options.fabric_half_thickness_m),
      k_N_per_m_(0.0),
      near_(static_cast<std::size_t>(patch.num_particles), 0) {
  // s^2 points per triangle: centroids of its s x s sub-triangles.
  const int s = options.pinch_samples_per_edge;
  double area_m2 = 0.0;
  for (const auto& t : patch.triangles) area_m2 += t.area_m2;
  if (!patch.triangles.empty()) {
    k_N_per_m_ = options.pad_stiffness_N_per_m3 * area_m2 /
                 static_cast<double>(patch.triangles.size() * static_cast<std::size_t>(s * s));
  }
  samples_.reserve(patch.triangles.size() * static_cast<std::size_t>(s * s));
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    auto add = [&](double b1, double b2) {
      Sample smp;
      smp.triangle = static_cast<int>(t);
      smp.w = {1.0 - b1 - b2, b1, b2};
      samples_.push_back(smp);
    };
    for (int i = 0; i < s; ++i) {
      for (int j = 0; i + j < s; ++j) {
        add((i + 1.0 / 3.0) / s, (j + 1.0 / 3.0) / s);
        if (i + j <= s - 2) add((i + 2.0 / 3.0) / s, (j + 2.0 / 3.0) / s);
      }
    }
  }
}

void PinchContact::Reset() {
  for (auto& s : samples_) s.active = false;
  active_ = false;
  num_active_ = 0;
}

double PinchContact::DepthInBoth(const Eigen::Vector3d& q) const {
  const double dt = (q - ClosestPointOnSegment(seg_thumb_.a_W, seg_thumb_.b_W, q)).norm();
  if (dt >= radius_thumb_m_) return radius_thumb_m_ - dt;
  const double di = (q - ClosestPointOnSegment(seg_index_.a_W, seg_index_.b_W, q)).norm();
  return std::min(radius_thumb_m_ - dt, radius_index_m_ - di);
}

Eigen::Vector3d PinchContact::SamplePosition(const Sample& s, const Eigen::VectorXd& x) const {
  const auto& p = patch_.triangles[static_cast<std::size_t>(s.triangle)].p;
  return s.w[0] * x.segment<3>(3 * p[0]) + s.w[1] * x.segment<3>(3 * p[1]) +
         s.w[2] * x.segment<3>(3 * p[2]);
}

bool PinchContact::Prepare(const FingerPose& thumb, const FingerPose& index, double grip_N,
                           const FrictionCoefficients& mu, const textile::FabricState& state,
                           std::vector<std::uint8_t>* owned, AnchorAccumulator* springs) {
  seg_thumb_ = CapsuleSegment(options_.thumb, thumb);
  seg_index_ = CapsuleSegment(options_.index, index);
  Eigen::Vector3d n, ct, ci;
  FingerFingerContact::Gap(options_, thumb, index, &n, &ct, &ci);
  // Contact plane midway between the two skins along the normal.
  origin_W_ = 0.5 * ((ct + options_.thumb.radius_m * n) + (ci - options_.index.radius_m * n));
  Eigen::Vector3d e1 = thumb.R_WF.col(0) - thumb.R_WF.col(0).dot(n) * n;
  if (e1.norm() < 1e-6) e1 = n.unitOrthogonal();
  e1.normalize();
  R_WC_.col(0) = e1;
  R_WC_.col(1) = n.cross(e1);
  R_WC_.col(2) = n;
  grip_N_ = grip_N;

  // Particles near the intersection: only their triangles can hold samples in it.
  const double reach = std::min(radius_thumb_m_ + 0.5 * options_.thumb.length_m,
                                radius_index_m_ + 0.5 * options_.index.length_m);
  const int np = patch_.num_particles;
  for (int p = 0; p < np; ++p) {
    const Eigen::Vector3d x = state.x_W_m.segment<3>(3 * p);
    near_[static_cast<std::size_t>(p)] = (x - origin_W_).squaredNorm() < reach * reach ? 1 : 0;
    if (near_[static_cast<std::size_t>(p)] && InsideBoth(x)) (*owned)[static_cast<std::size_t>(p)] = 1;
  }
  // Let triangles with a near particle count as near (their samples may be inside).
  num_active_ = 0;
  weight_sum_ = 0.0;
  for (Sample& s : samples_) {
    const auto& p = patch_.triangles[static_cast<std::size_t>(s.triangle)].p;
    const bool near = near_[static_cast<std::size_t>(p[0])] || near_[static_cast<std::size_t>(p[1])] ||
                      near_[static_cast<std::size_t>(p[2])];
    if (!near) {
      s.active = false;
      continue;
    }
    const Eigen::Vector3d q = SamplePosition(s, state.x_W_m);
    const double depth = DepthInBoth(q);
    if (depth <= 0.0) {
      s.active = false;
      continue;
    }
    const double ramp = options_.pinch_edge_ramp_m;
    s.k_N_per_m = k_N_per_m_ * (ramp > 0.0 ? std::min(1.0, depth / ramp) : 1.0);
    if (!s.active) {
      // A new sample sticks where it meets the plane (paper: "initially static contact").
      const Eigen::Vector3d q_C = R_WC_.transpose() * (q - origin_W_);
      s.ideal_C = q_C.head<2>();
      s.active = true;
      s.sliding = false;
    }
    ++num_active_;
    weight_sum_ += s.k_N_per_m;
  }
  active_ = num_active_ > 0;
  if (!active_) return false;

  // Each sample's share of the grip is in proportion to its spring (full inside, ramped at the edge).
  const double grip_per_stiffness = grip_N_ / weight_sum_;
  const FrictionCoefficients two_faces{2.0 * mu.mu_static, 2.0 * mu.mu_dynamic};
  for (Sample& s : samples_) {
    if (!s.active) continue;
    const Eigen::Vector3d q = SamplePosition(s, state.x_W_m);
    const Eigen::Vector3d held_W = origin_W_ + R_WC_.col(0) * s.ideal_C.x() + R_WC_.col(1) * s.ideal_C.y();
    const Eigen::Vector3d free_W = q - (q - origin_W_).dot(n) * n;
    const StickSlipResult r = UpdateStickSlip(held_W, free_W, s.k_N_per_m, grip_per_stiffness * s.k_N_per_m,
                                              two_faces, s.sliding);
    s.sliding = r.sliding;
    s.ideal_C = (R_WC_.transpose() * (r.held_W - origin_W_)).head<2>();
    s.anchor_W = origin_W_ + R_WC_.col(0) * s.ideal_C.x() + R_WC_.col(1) * s.ideal_C.y();
    // Lumped onto the particles: stiffness w k and the anchor that gives the same force now.
    const auto& p = patch_.triangles[static_cast<std::size_t>(s.triangle)].p;
    for (int m = 0; m < 3; ++m) {
      const double w = s.w[static_cast<std::size_t>(m)];
      if (w <= 0.0) continue;
      const int pm = p[static_cast<std::size_t>(m)];
      if (state.mode[static_cast<std::size_t>(pm)] != textile::ParticleMode::kFree) continue;
      springs->Add(pm, w * s.k_N_per_m, state.x_W_m.segment<3>(3 * pm) + (s.anchor_W - q));
    }
  }
  return true;
}

void PinchContact::Resolve(const textile::FabricState& state, const Eigen::MatrixX2d& rest_uv_m,
                           PinchResult* result) {
  *result = PinchResult{};
  result->active = active_;
  result->normal_W = R_WC_.col(2);
  if (!active_) return;
  result->grip_N = grip_N_;
  const Eigen::Vector3d n = R_WC_.col(2);
  for (Sample& s : samples_) {
    if (!s.active) continue;
    const Eigen::Vector3d q = SamplePosition(s, state.x_W_m);
    result->fabric_force_W_N += s.k_N_per_m * (s.anchor_W - q);
    const Eigen::Vector3d free_W = q - (q - origin_W_).dot(n) * n;
    result->friction_W_N += s.k_N_per_m * (free_W - s.anchor_W);

    const auto& p = patch_.triangles[static_cast<std::size_t>(s.triangle)].p;
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    Eigen::Vector3d vel = Eigen::Vector3d::Zero();
    for (int m = 0; m < 3; ++m) {
      const int pm = p[static_cast<std::size_t>(m)];
      uv += s.w[static_cast<std::size_t>(m)] * rest_uv_m.row(pm).transpose();
      vel += s.w[static_cast<std::size_t>(m)] * state.v_W_m_per_s.segment<3>(3 * pm);
    }
    result->touch_uv_m += uv;
    result->touch_velocity_W += vel;
    result->touch_triangle = s.triangle;
    ++result->samples;
    if (s.sliding) ++result->sliding_samples;
  }
  if (result->samples > 0) {
    result->touch_uv_m /= result->samples;
    result->touch_velocity_W /= result->samples;
  }
}

}  // namespace haptex::contact
