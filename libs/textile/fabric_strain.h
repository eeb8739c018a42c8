#pragma once
// The cloth's largest tensile strain: the measure the accuracy benchmarks compare and the
// stepper's strain bound watches.

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"

namespace haptex::textile {

/// Largest warp or weft strain |U| - 1 (|V| - 1) over the triangles at positions x [-]; the most
/// compressed value when every element is compressed. 0 for a model without triangles.
double LargestTensileStrain(const FabricModel& model, const Eigen::VectorXd& x_W_m);

}  // namespace haptex::textile
