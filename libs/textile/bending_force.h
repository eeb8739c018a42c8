#pragma once
// Volino's linear anisotropic bending on grid lines (Volino & Magnenat-Thalmann 2006/2007,
// docs/physics-reference.md section 3.2), with bending damping. Constant Jacobian.

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// Per triplet along a warp (weft) line: R = sum alpha_k x_k, force -lambda alpha_k (R + bend_s
/// R_dot), with lambda = 2 B w / (l0 + l1) so that the energy equals B kappa^2 / 2 per area.
void AddBendingForces(const FabricModel& model, const Eigen::VectorXd& x_W_m, const Eigen::VectorXd& v_W_m_per_s,
                      ForceSink* sink);

}  // namespace haptex::textile
