#pragma once
// Gravity and applied loads (point and edge loads set in FabricState::external_force_W_N).

#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// f_p += m_p g + external_force_p. No Jacobian (loads do not depend on the state).
void AddExternalForces(const FabricModel& model, const FabricState& state, ForceSink* sink);

/// Spreads `total_W_N` over a chain of particles (e.g. one edge, in order along it) in proportion
/// to the rest length each represents, and adds it to state->external_force_W_N.
/// @throws std::invalid_argument for fewer than 1 particle or an out-of-range index.
void AddEdgeLoad(const FabricModel& model, const std::vector<int>& chain, const Eigen::Vector3d& total_W_N,
                 FabricState* state);

/// Sets the load of particle p (point load), replacing any previous value.
void SetPointLoad(int p, const Eigen::Vector3d& force_W_N, FabricState* state);

}  // namespace haptex::textile
