#pragma once
// The conversions every service's codec shares between messages (proto/haptex/v1/common.proto) and
// the cores' types: vectors, orientations, and which finger a message names. One place for each,
// so the services agree on slots and on what a malformed value becomes.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "haptex/v1/common.pb.h"

namespace haptex::codec {

/// The cores' finger slots: 0 the thumb, 1 the index finger.
inline constexpr int kThumbSlot = 0;
inline constexpr int kIndexSlot = 1;
inline constexpr int kFingerSlots = 2;

/// The slot of `finger`, or -1 for FINGER_UNSPECIFIED and unknown values.
inline int FingerSlot(v1::Finger finger) {
  switch (finger) {
    case v1::FINGER_THUMB:
      return kThumbSlot;
    case v1::FINGER_INDEX:
      return kIndexSlot;
    default:
      return -1;
  }
}
/// The finger of slot 0 or 1.
inline v1::Finger FingerOfSlot(int slot) { return slot == kThumbSlot ? v1::FINGER_THUMB : v1::FINGER_INDEX; }
/// "thumb", "index" or "unspecified", for files and messages people read.
inline const char* FingerName(v1::Finger finger) {
  switch (finger) {
    case v1::FINGER_THUMB:
      return "thumb";
    case v1::FINGER_INDEX:
      return "index";
    default:
      return "unspecified";
  }
}

inline Eigen::Vector3d ToEigen(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }
inline void ToMessage(const Eigen::Vector3d& v, v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

/// The rotation a quaternion message names, normalised; identity when it is far from unit length
/// (norm below 0.5: missing or garbage) or not finite.
inline Eigen::Matrix3d ToRotation(const v1::Quat& q) {
  const Eigen::Quaterniond quat(q.w(), q.x(), q.y(), q.z());
  const double norm = quat.norm();
  if (!(norm > 0.5) || !std::isfinite(norm)) return Eigen::Matrix3d::Identity();
  return quat.normalized().toRotationMatrix();
}
inline void ToMessage(const Eigen::Quaterniond& q, v1::Quat* out) {
  out->set_w(q.w());
  out->set_x(q.x());
  out->set_y(q.y());
  out->set_z(q.z());
}

}  // namespace haptex::codec
