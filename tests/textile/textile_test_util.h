#pragma once
// Shared helpers of the textile tests: test fabrics, scenario set-up, static solves, Jacobian checks.

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "libs/textile/fabric_model.h"
#include "libs/textile/fabric_state.h"
#include "libs/textile/fabric_stepper.h"
#include "libs/textile/force_sink.h"
#include "libs/textile/kes_fabric.h"

namespace haptex::textile::testing {

/// A test-only composite "stiff woven": the KES tensile values of Kumari & Khurana 2016 denim B
/// (EMT 5.735 %, LT 0.655, both directions; docs/physics-reference.md section 1.2) with the mass,
/// shear and bending of the Wang 2011 11 oz denim (the Kumari table's W is unusable). Not a
/// database fabric.
kes::Fabric CompositeDenim();

/// `m` with every stiffness (tensile, shear, bending) multiplied by `factor`.
FabricMaterial ScaleStiffness(const FabricMaterial& m, double factor);

/// Element force function under test: adds forces (and Jacobians if the sink wants them).
using ForceFn = std::function<void(const FabricModel&, const Eigen::VectorXd& x,
                                   const Eigen::VectorXd& v, ForceSink*)>;

/// Dense force, df/dx and df/dv of `fn` at (x, v).
void DenseForceAndJacobians(const FabricModel& model, const ForceFn& fn, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& v, Eigen::VectorXd* f, Eigen::MatrixXd* dfdx,
                            Eigen::MatrixXd* dfdv);
/// Central finite differences of `fn` with respect to x (wrt_v false) or v (wrt_v true).
Eigen::MatrixXd FiniteDifferenceJacobian(const FabricModel& model, const ForceFn& fn,
                                         const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                         bool wrt_v, double step);

/// Particles of the row i_u = const (a weft line), ordered along v.
std::vector<int> WarpRow(const FabricModel& model, int i_u);

/// Steps until every speed is below `speed_tol_m_per_s` for 5 consecutive steps, or max_steps.
/// Returns the steps taken.
int RunToRest(FabricStepper* stepper, FabricState* state, int max_steps, double speed_tol_m_per_s);

/// Elongation under a hanging load: exact integral of the inverse tensile curve along the strip.
/// L rest length, b width, rho areal density, load P at the bottom, gravity g.
double AnalyticHangingElongation(const StrainCurve& curve, double length_m, double width_m,
                                 double rho_kg_per_m2, double load_N, double g_m_per_s2);

}  // namespace haptex::textile::testing
