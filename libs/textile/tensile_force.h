#pragma once
// Nonlinear tensile force along warp and weft, with stretch damping (paper section 3.2.2).

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// Per triangle: warp strain |U| - 1 and weft strain |V| - 1 through the material's tensile
/// curves, force -A0 sigma a_k U/|U| (and b_k for weft); damping sigma_d = stretch_s * slope *
/// strain rate. Jacobian: the exact tangent, with the transverse (geometric) term dropped under
/// compression so the system stays positive definite; damping's position derivative is dropped.
void AddTensileForces(const FabricModel& model, const Eigen::VectorXd& x_W_m, const Eigen::VectorXd& v_W_m_per_s,
                      ForceSink* sink);

}  // namespace haptex::textile
