#pragma once
// Shared helpers of the textile tests: the validation scenarios (libs/textile/validation.h, shared
// with the benchmarks) under their test names, and the dense Jacobians of a force function.

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/force_sink.h"
#include "libs/textile/kes_fabric.h"
#include "libs/textile/validation.h"

namespace haptex::textile::testing {

using validation::AnalyticHangingElongation;
using validation::CompositeDenim;
using validation::RunToRest;
using validation::ScaleStiffness;
using validation::WarpRow;

/// Element force function under test: adds forces (and Jacobians if the sink wants them).
using ForceFn = std::function<void(const FabricModel&, const Eigen::VectorXd& x, const Eigen::VectorXd& v, ForceSink*)>;

/// Dense force, df/dx and df/dv of `fn` at (x, v).
void DenseForceAndJacobians(const FabricModel& model, const ForceFn& fn, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& v, Eigen::VectorXd* f, Eigen::MatrixXd* dfdx, Eigen::MatrixXd* dfdv);
/// Central finite differences of `fn` with respect to x (wrt_v false) or v (wrt_v true).
Eigen::MatrixXd FiniteDifferenceJacobian(const FabricModel& model, const ForceFn& fn, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd& v, bool wrt_v, double step);

}  // namespace haptex::textile::testing
