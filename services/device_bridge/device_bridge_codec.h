#pragma once
// The bridge core's plain types <-> the haptex messages.

#include "haptex/v1/finger_states.pb.h"
#include "haptex/v1/force_model.pb.h"
#include "libs/device/device_bridge.h"

namespace haptex::device_bridge {

/// FINGER_THUMB / FINGER_INDEX -> Manipulator; false for anything else.
bool ToManipulator(v1::Finger finger, device::Manipulator* out);
v1::Finger ToFinger(device::Manipulator manipulator);

/// A ForceModel message entry -> the core's ForceModel. Values are copied as they are (NaN
/// included): the safety stage, not the parser, decides what reaches the device. A stiffness
/// without 9 values is treated as zero stiffness.
device::ForceModel ToForceModel(const v1::FingerForceModel& in);
/// The same, with the other finger's entry of the same ForceModel for the cross term's anchor
/// (null: no other finger, no cross term).
device::ForceModel ToForceModel(const v1::FingerForceModel& in, const v1::FingerForceModel* other);

/// Stiffnesses of exactly 9 values (or none: zero stiffness). Anything else is a malformed model,
/// refused and counted rather than applied as a constant force.
bool IsWellFormed(const v1::FingerForceModel& in);

/// Fills `out` (reused, no allocation once it has two fingers) from the bridge's finger states.
void FillFingerStates(const device::DeviceBridge& bridge, v1::FingerStates* out);

}  // namespace haptex::device_bridge
