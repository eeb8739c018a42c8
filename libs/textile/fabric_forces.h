#pragma once
// Sum of every force acting on the fabric.

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// Adds tensile, shear, bending, damping, drag, gravity and applied loads into `sink` (which the
/// caller zeroes). Never allocates.
void AccumulateForces(const FabricModel& model, const FabricState& state, ForceSink* sink);

}  // namespace haptex::textile
