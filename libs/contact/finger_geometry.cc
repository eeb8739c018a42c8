#include "libs/contact/finger_geometry.h"

#include <algorithm>
#include <cmath>

namespace haptex::contact {

FingerPose PoseFacing(const Eigen::Vector3d& centre_W, const Eigen::Vector3d& pad_normal_W,
                      const Eigen::Vector3d& distal_W) {
  FingerPose pose;
  pose.p_W_m = centre_W;
  const Eigen::Vector3d z = pad_normal_W.normalized();
  const Eigen::Vector3d x = (distal_W - distal_W.dot(z) * z).normalized();
  pose.R_WF.col(0) = x;
  pose.R_WF.col(1) = z.cross(x);
  pose.R_WF.col(2) = z;
  return pose;
}

Segment CapsuleSegment(const FingerShape& shape, const FingerPose& pose) {
  const Eigen::Vector3d half = pose.R_WF.col(0) * (0.5 * shape.length_m);
  return {pose.p_W_m - half, pose.p_W_m + half};
}

Eigen::Vector3d ClosestPointOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& q) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double t = std::clamp((q - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

void ClosestPointsBetweenSegments(const Segment& first, const Segment& second, Eigen::Vector3d* on_first,
                                  Eigen::Vector3d* on_second) {
  // Ericson, Real-Time Collision Detection, 5.1.9 (clamped parameters).
  const Eigen::Vector3d d1 = first.b_W - first.a_W;
  const Eigen::Vector3d d2 = second.b_W - second.a_W;
  const Eigen::Vector3d r = first.a_W - second.a_W;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0.0, t = 0.0;
  constexpr double kEps = 1e-18;
  if (a <= kEps && e <= kEps) {
    s = t = 0.0;
  } else if (a <= kEps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kEps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > kEps * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.5;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  *on_first = first.a_W + s * d1;
  *on_second = second.a_W + t * d2;
}

SurfaceQuery QueryCapsule(const Segment& segment, double radius_m, const Eigen::Vector3d& q_W,
                          const Eigen::Vector3d& fallback_normal_W) {
  const Eigen::Vector3d c = ClosestPointOnSegment(segment.a_W, segment.b_W, q_W);
  const Eigen::Vector3d d = q_W - c;
  const double dist = d.norm();
  SurfaceQuery out;
  out.normal_W = dist > 1e-12 ? Eigen::Vector3d(d / dist) : fallback_normal_W;
  out.depth_m = radius_m - dist;
  out.surface_W = c + radius_m * out.normal_W;
  return out;
}

Eigen::Vector3d ProjectOntoCapsule(const Segment& segment, double radius_m, const Eigen::Vector3d& q_W,
                                   const Eigen::Vector3d& fallback_normal_W) {
  return QueryCapsule(segment, radius_m, q_W, fallback_normal_W).surface_W;
}

}  // namespace haptex::contact
