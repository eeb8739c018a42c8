#pragma once
// local_contact's messages <-> the contact and dual-layer cores: finger states in, force models,
// touch traces and patch results out, patches in. No allocation once the messages have their
// fingers (and the patch arrays their capacity).

#include <array>
#include <cstdint>

#include "haptex/v1/finger_states.pb.h"
#include "haptex/v1/force_model.pb.h"
#include "haptex/v1/local_patch.pb.h"
#include "haptex/v1/touch_trace.pb.h"
#include "libs/contact/contact_solver.h"
#include "libs/dual_layer/patch_data.h"
#include "libs/dual_layer/patch_result.h"

namespace haptex::local_contact {

v1::ContactState ToMessage(contact::ContactState state);

/// The fingers the contact models see: each finger of the scene (`scene_fingers`, by slot) where
/// it is when the bridge applies the force (the measured pose when none is predicted); a finger
/// marked in `ahead` a haptic round trip further (where it is when this answer reaches the
/// bridge: a finger approaching the fabric is met there in time). None while the device is not
/// ok: no force from fingers the bridge cannot see. With `at_bridge`, each finger's position when
/// the bridge applies the force, whichever pose it was given.
std::array<contact::FingerInput, 2> FingerInputs(const v1::FingerStates& states,
                                                 const std::array<bool, 2>& scene_fingers,
                                                 const std::array<bool, 2>& ahead = {false, false},
                                                 std::array<Eigen::Vector3d, 2>* at_bridge = nullptr);

/// Both fingers' models (F0, K, x0 at the pose they were computed for) into `out`; zero force and
/// stiffness for a finger that is not present or without contact output (`contact` null).
void FillForceModel(const contact::ContactOutput* contact, const std::array<contact::FingerInput, 2>& fingers,
                    std::uint64_t based_on_controller_sequence, double ttl_s, v1::ForceModel* out);
/// `model` with every force and stiffness zero (what local_contact sends as it stops).
void ZeroForceModel(v1::ForceModel* model);

void FillTouchTrace(const contact::ContactOutput& contact, double sim_time_s, v1::TouchTrace* out);

enum class PatchCopy { kOk, kTooLarge, kMalformed };
/// Copies a received patch into `out` (whose arrays keep their capacity: a patch larger than the
/// capacity is refused, not grown) and checks that it can be built (dual_layer::IsBuildable with
/// ids below `max_particle_id`).
PatchCopy CopyPatch(const v1::LocalPatch& patch, std::uint32_t max_particle_id, dual_layer::PatchData* out);

/// The result as sent to global_sim (reusing `out`'s storage).
void ToMessage(const dual_layer::PatchResultData& result, v1::PatchResult* out);

}  // namespace haptex::local_contact
