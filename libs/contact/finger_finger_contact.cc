#include "libs/contact/finger_finger_contact.h"

#include "libs/contact/coulomb_friction.h"

namespace haptex::contact {

FingerFingerContact::FingerFingerContact(const ContactOptions& options) : options_(options) {}

void FingerFingerContact::Reset() {
  touching_ = false;
  sliding_ = false;
}

double FingerFingerContact::Gap(const ContactOptions& o, const FingerPose& thumb, const FingerPose& index,
                                Eigen::Vector3d* normal_W, Eigen::Vector3d* closest_thumb_W,
                                Eigen::Vector3d* closest_index_W) {
  Eigen::Vector3d ct, ci;
  ClosestPointsBetweenSegments(CapsuleSegment(o.thumb, thumb), CapsuleSegment(o.index, index), &ct, &ci);
  const Eigen::Vector3d d = ci - ct;
  const double dist = d.norm();
  // Coincident axes: fall back to the thumb's pad normal (the palmar sides face each other).
  *normal_W = dist > 1e-9 ? Eigen::Vector3d(d / dist) : Eigen::Vector3d(thumb.R_WF.col(2));
  if (closest_thumb_W) *closest_thumb_W = ct;
  if (closest_index_W) *closest_index_W = ci;
  return dist - o.thumb.radius_m - o.index.radius_m;
}

FingerFingerResult FingerFingerContact::Update(const FingerPose& thumb, const FingerPose& index, double gap_offset_m,
                                               const FrictionCoefficients& mu, bool with_friction) {
  FingerFingerResult r;
  Eigen::Vector3d n, ct;
  const double gap = Gap(options_, thumb, index, &n, &ct, nullptr) - gap_offset_m;
  if (gap >= 0.0) {
    touching_ = false;
    sliding_ = false;
    r.normal_W = n;
    return r;
  }
  r.touching = true;
  r.normal_W = n;
  r.penetration_m = -gap;
  r.normal_N = options_.finger_finger_normal_N_per_m * r.penetration_m;
  const double kt = options_.finger_finger_tangential_N_per_m;
  const Eigen::Matrix3d nn = n * n.transpose();
  const Eigen::Matrix3d tangent_projector = Eigen::Matrix3d::Identity() - nn;
  Eigen::Vector3d tangential = Eigen::Vector3d::Zero();
  // The touching point on the thumb's surface: where the proxy would be without friction.
  const Eigen::Vector3d free_W = ct + options_.thumb.radius_m * n;
  if (with_friction) {
    if (!touching_) {
      held_thumb_F_ = thumb.ToFinger(free_W);
      sliding_ = false;
    }
    const Eigen::Vector3d held_W = thumb.ToWorld(held_thumb_F_);
    const StickSlipResult s = UpdateStickSlip(held_W, free_W, kt, r.normal_N, mu, sliding_);
    sliding_ = s.sliding;
    held_thumb_F_ = thumb.ToFinger(s.held_W);
    // The spring pulls the index's touching point back towards the held point, in the tangent
    // plane (the normal direction belongs to the normal spring).
    tangential = kt * (tangent_projector * (s.held_W - free_W));
    r.sliding = s.sliding;
  }
  touching_ = true;
  r.tangential_N = tangential.norm();
  r.force_on_index_W_N = r.normal_N * n + tangential;
  r.stiffness_index_W_N_per_m = -options_.finger_finger_normal_N_per_m * nn;
  if (with_friction && !sliding_) r.stiffness_index_W_N_per_m -= kt * tangent_projector;
  return r;
}

}  // namespace haptex::contact
