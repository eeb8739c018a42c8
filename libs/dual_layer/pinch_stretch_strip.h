#pragma once
// The scenario the dual layer is checked and measured on (its consistency test and speed/accuracy
// sweep): a 3 x 8 cm strip hanging from a clamp at z = 0 (warp down, weft along x), pinched 6 cm
// below the clamp and pulled down 3 mm.

#include <array>

#include "libs/contact/contact_solver.h"
#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/kes_material.h"

namespace haptex::dual_layer {

struct Strip {
  textile::FabricModel model;
  textile::FabricState state;
};
/// The strip with particles `spacing_m` apart, at rest, its top row clamped.
Strip PinchStretchStrip(const textile::FabricMaterial& material, double spacing_m);
/// The fingers at time t: approach and squeeze (0.3 s), hold, pull down 3 mm (0.5-2.0 s), hold.
std::array<contact::FingerInput, 2> PinchStretchFingers(double t_s, const contact::ContactOptions& o);

}  // namespace haptex::dual_layer
