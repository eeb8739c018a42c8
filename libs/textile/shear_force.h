#pragma once
// Shear force from the warp/weft angle, estimated by U.V (paper section 3.2.2), with damping.

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// Per triangle: gamma = U.V (about the warp/weft angle change [rad]), tau = shear(gamma),
/// force -A0 (tau + shear_s * slope * gamma_dot) (a_k V + b_k U). Jacobian keeps the
/// positive-semidefinite part slope * g g^T (the indefinite tau-term is dropped).
void AddShearForces(const FabricModel& model, const Eigen::VectorXd& x_W_m, const Eigen::VectorXd& v_W_m_per_s,
                    ForceSink* sink);

}  // namespace haptex::textile
