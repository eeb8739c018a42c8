#pragma once
// The cloth's potential energy, for energy balances in tests and benchmarks (the step never
// needs it: the forces are its negative gradient, up to the Jacobians' documented omissions).

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"

namespace haptex::textile {

/// Strain energy (tensile, shear, bending) plus gravity's potential relative to the world
/// origin plus the anchor springs' energy [J]. The laws are integrated by Gauss-Legendre between
/// their spline's knots: exact to round-off for their cubic pieces.
double PotentialEnergy(const FabricModel& model, const FabricState& state);

/// KineticEnergy + PotentialEnergy [J].
double TotalEnergy(const FabricModel& model, const FabricState& state);

}  // namespace haptex::textile
