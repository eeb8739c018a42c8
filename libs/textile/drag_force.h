#pragma once
// Air drag on still air: linear (viscous, per particle area) and quadratic (normal to each
// triangle), paper section 3.2.2 "external viscous and higher order velocity-dependent damping".

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/force_sink.h"

namespace haptex::textile {

/// Linear: f_p = -c A_p v_p. Quadratic: per triangle, F = -rho C_d A (v.n)|v.n| n / 2 with v the
/// mean velocity, shared equally by its corners. Velocity Jacobians are exact for fixed normals;
/// the position derivative of the normal is dropped.
void AddDragForces(const FabricModel& model, const Eigen::VectorXd& x_W_m, const Eigen::VectorXd& v_W_m_per_s,
                   ForceSink* sink);

}  // namespace haptex::textile
