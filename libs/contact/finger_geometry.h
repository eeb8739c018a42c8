#pragma once
// Fingertip shape in the finger frame F and the distance queries contact needs.
// F (docs/grab-protocol.md): origin at the fingertip centre, +x_F the distal axis (towards the
// nail tip), +z_F the pad's outward normal. A capsule's segment lies on x_F; a sphere is a
// capsule of zero length.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace haptex::contact {

struct FingerShape {
  double radius_m = 0.008;
  double length_m = 0.012;  ///< capsule segment length along x_F; 0 = sphere
};

/// Pose of F in the world frame W.
struct FingerPose {
  Eigen::Vector3d p_W_m{Eigen::Vector3d::Zero()};
  Eigen::Matrix3d R_WF{Eigen::Matrix3d::Identity()};

  Eigen::Vector3d ToWorld(const Eigen::Vector3d& p_F) const { return p_W_m + R_WF * p_F; }
  Eigen::Vector3d ToFinger(const Eigen::Vector3d& p_W) const { return R_WF.transpose() * (p_W - p_W_m); }
};

/// A pose centred at `centre_W` whose pad (+z_F) faces `pad_normal_W`, with the distal axis (+x_F)
/// along `distal_W` (its part along the pad normal removed). Neither may be zero, nor may they be
/// parallel.
FingerPose PoseFacing(const Eigen::Vector3d& centre_W, const Eigen::Vector3d& pad_normal_W,
                      const Eigen::Vector3d& distal_W);

/// Segment end points of a capsule in W.
struct Segment {
  Eigen::Vector3d a_W, b_W;
};
Segment CapsuleSegment(const FingerShape& shape, const FingerPose& pose);

/// Closest point to q on segment [a, b].
Eigen::Vector3d ClosestPointOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& q);

/// Closest points between two segments (s on the first, t on the second).
void ClosestPointsBetweenSegments(const Segment& first, const Segment& second, Eigen::Vector3d* on_first,
                                  Eigen::Vector3d* on_second);

/// Where a point is relative to a capsule of radius `radius_m` (the finger radius plus any
/// contact offset): depth > 0 inside; surface point and outward unit normal at the nearest
/// surface point. On the axis itself the normal falls back to `fallback_normal_W`.
struct SurfaceQuery {
  double depth_m = 0.0;
  Eigen::Vector3d surface_W{Eigen::Vector3d::Zero()};
  Eigen::Vector3d normal_W{Eigen::Vector3d::UnitZ()};
};
SurfaceQuery QueryCapsule(const Segment& segment, double radius_m, const Eigen::Vector3d& q_W,
                          const Eigen::Vector3d& fallback_normal_W);

/// Projects q onto the capsule surface (radius_m): the nearest surface point.
Eigen::Vector3d ProjectOntoCapsule(const Segment& segment, double radius_m, const Eigen::Vector3d& q_W,
                                   const Eigen::Vector3d& fallback_normal_W);

}  // namespace haptex::contact
