#pragma once
// The cloth's largest tensile strain: the measure the accuracy benchmarks compare and the
// stepper's strain bound watches.

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"

namespace haptex::textile {

/// The triangle's yarn vectors at positions x: U = sum a_k x_k (warp), V = sum b_k x_k (weft);
/// |U| - 1 and |V| - 1 are its strains, U.V its shear.
void YarnVectors(const TriangleElement& e, const Eigen::VectorXd& x_W_m, Eigen::Vector3d* u, Eigen::Vector3d* v);

/// Largest warp or weft strain |U| - 1 (|V| - 1) over the triangles at positions x [-]; the most
/// compressed value when every element is compressed. 0 for a model without triangles.
double LargestTensileStrain(const FabricModel& model, const Eigen::VectorXd& x_W_m);

}  // namespace haptex::textile
