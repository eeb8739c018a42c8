#pragma once
// Springs from particles to moving anchors (FabricState::anchor_*): how finger contact acts on
// the fabric. Stiff (contact springs reach 10^3 N/m on particles of 10^-6 kg), so both
// integrators treat them implicitly.

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// f_p += k_p (anchor_p - x_p) with Jacobian -k_p I on the diagonal block (free particles).
/// No-op when the state carries no anchor arrays.
void AddAnchorSpringForces(const FabricModel& model, const FabricState& state, ForceSink* sink);

/// Largest k_p / m_p over the particles [1/s^2] (0 without anchors).
double MaxAnchorStiffnessPerMass(const FabricModel& model, const FabricState& state);

}  // namespace haptex::textile
